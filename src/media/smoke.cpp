#include "smokescan/media/smoke.hpp"

#include <algorithm>

namespace smokescan {

std::shared_ptr<const DensityGrid> SmokeVolume::gridAt(double t_s) const
{
    if (auto g = std::get_if<std::shared_ptr<const DensityGrid>>(&source)) return *g;
    return std::make_shared<const DensityGrid>(rasterisePlume(std::get<PlumeConfig>(source), t_s));
}

SmokeField SmokeField::at(const std::vector<SmokeVolume>& volumes, double t_s)
{
    SmokeField f;
    for (const SmokeVolume& v : volumes) {
        const double s = v.timeline.at(t_s);
        if (s <= 0) continue;
        Entry& e = f.entries_.emplace_back();
        e.volume = &v;
        e.grid = v.gridAt(t_s);
        e.scale = s;
        e.reach = e.grid->worldBounds();
        if (!e.reach.empty()) {
            const double pad = e.grid->voxelSize();
            e.reach.lo.array() -= pad;
            e.reach.hi.array() += pad;
        }
    }
    return f;
}

void SmokeField::prepare(double wavelength_nm)
{
    for (Entry& e : entries_) {
        e.wavelength_nm = wavelength_nm;
        e.sigma_t = e.volume->medium.sigmaT(wavelength_nm);
    }
}

SmokeField SmokeField::scaledRegional(double k) const
{
    SmokeField f = *this;
    for (Entry& e : f.entries_)
        if (e.volume->role == SmokeRole::Regional) e.scale *= k;
    return f;
}

BeamSmoke SmokeField::trace(const Ray& ray, double t0, double t1, const BeamQuery& q) const
{
    BeamSmoke out;
    trace(ray, t0, t1, q, out);
    return out;
}

void SmokeField::trace(const Ray& ray, double t0, double t1, const BeamQuery& q, BeamSmoke& out) const
{
    out.column_regional = out.column_local = out.tau = 0;
    out.first_local_m = kInf;
    out.sigma_t_profile.clear();
    out.beta_profile.clear();
    // Each volume's profile, kept for each thread with its storage (a frame traces many beams).
    thread_local std::vector<std::vector<ProfileSegment>> parts, beta_parts;
    size_t used = 0;  // volumes with smoke on the beam, in parts[0, used)
    // The beam against each grid's bounds first (most beams miss most grids): its inverse
    // direction once, then a slab test a grid instead of the walk's setup in index space.
    const Vec3 inv_d = Aabb::inverseDirection(ray);
    auto misses = [&](const Aabb& b) {
        double lo = t0, hi = t1;
        return !b.clip(ray, inv_d, lo, hi);
    };
    for (const Entry& e : entries_) {
        if (misses(e.reach)) continue;  // nothing of this grid on the beam: it adds nothing
        const double sigma = e.wavelength_nm == q.wavelength_nm ? e.sigma_t : e.volume->medium.sigmaT(q.wavelength_nm);
        if (q.want_profile && parts.size() <= used) parts.resize(used + 1), beta_parts.resize(used + 1);
        std::vector<ProfileSegment>* prof = q.want_profile ? &parts[used] : nullptr;
        if (prof) prof->clear();
        const double col = e.scale * e.grid->integrate(ray, t0, t1, q.recon, prof);
        out.tau += sigma * col;
        if (e.volume->role == SmokeRole::Regional) {
            out.column_regional += col;
        } else {
            out.column_local += col;
            if (std::isfinite(q.local_threshold) && col > 0)
                out.first_local_m =
                    std::min(out.first_local_m, e.grid->firstAbove(ray, t0, t1, q.local_threshold / e.scale));
        }
        if (prof && !prof->empty()) {
            // σ_t and β on the same segments, in one pass.
            const double k_t = e.scale * sigma, bpe = e.volume->medium.backscatterPerExtinction();
            std::vector<ProfileSegment>& beta = beta_parts[used];
            beta.resize(prof->size());
            for (size_t i = 0; i < prof->size(); ++i) {
                ProfileSegment& g = (*prof)[i];
                g.density *= k_t;
                beta[i] = {g.t0_m, g.t1_m, g.density * bpe};
            }
            ++used;
        }
    }
    if (!q.want_profile || used == 0) return;
    if (used == 1) {  // one volume on the beam: its own profiles (storage swapped, not copied)
        out.sigma_t_profile.swap(parts.front());
        out.beta_profile.swap(beta_parts.front());
    } else {
        sumProfiles(parts.data(), used, out.sigma_t_profile);
        sumProfiles(beta_parts.data(), used, out.beta_profile);
    }
}

std::vector<ProfileSegment> sumProfiles(const std::vector<std::vector<ProfileSegment>>& parts)
{
    std::vector<ProfileSegment> out;
    sumProfiles(parts.data(), parts.size(), out);
    return out;
}

void sumProfiles(const std::vector<ProfileSegment>* parts, size_t n_parts, std::vector<ProfileSegment>& out)
{
    out.clear();
    if (n_parts == 1) {
        out = parts[0];
        return;
    }
    thread_local std::vector<double> cuts;
    thread_local std::vector<size_t> idx;
    cuts.clear();
    for (size_t k = 0; k < n_parts; ++k)
        for (const auto& s : parts[k]) {
            cuts.push_back(s.t0_m);
            cuts.push_back(s.t1_m);
        }
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
    idx.assign(n_parts, 0);
    for (size_t i = 0; i + 1 < cuts.size(); ++i) {
        const double a = cuts[i], b = cuts[i + 1], m = 0.5 * (a + b);
        double v = 0;
        for (size_t k = 0; k < n_parts; ++k) {
            const auto& p = parts[k];
            while (idx[k] < p.size() && p[idx[k]].t1_m <= m) ++idx[k];
            if (idx[k] < p.size() && p[idx[k]].t0_m <= m) v += p[idx[k]].density;
        }
        if (v == 0) continue;
        if (!out.empty() && out.back().t1_m == a && out.back().density == v)
            out.back().t1_m = b;
        else
            out.push_back({a, b, v});
    }
}

}  // namespace smokescan
