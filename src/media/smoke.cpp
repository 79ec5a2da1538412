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
        f.entries_.push_back({&v, v.gridAt(t_s), s});
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
    std::vector<std::vector<ProfileSegment>> parts, beta_parts;
    for (const Entry& e : entries_) {
        const double sigma = e.wavelength_nm == q.wavelength_nm ? e.sigma_t : e.volume->medium.sigmaT(q.wavelength_nm);
        std::vector<ProfileSegment> prof;
        const double col = e.scale * e.grid->integrate(ray, t0, t1, q.recon, q.want_profile ? &prof : nullptr);
        out.tau += sigma * col;
        if (e.volume->role == SmokeRole::Regional) {
            out.column_regional += col;
        } else {
            out.column_local += col;
            if (std::isfinite(q.local_threshold) && col > 0)
                out.first_local_m =
                    std::min(out.first_local_m, e.grid->firstAbove(ray, t0, t1, q.local_threshold / e.scale));
        }
        if (q.want_profile && !prof.empty()) {
            for (auto& s : prof) s.density *= e.scale * sigma;
            std::vector<ProfileSegment> beta = prof;
            const double bpe = e.volume->medium.backscatterPerExtinction();
            for (auto& s : beta) s.density *= bpe;
            parts.push_back(std::move(prof));
            beta_parts.push_back(std::move(beta));
        }
    }
    if (q.want_profile && parts.size() == 1) {  // one volume on the beam: its own profiles
        out.sigma_t_profile = std::move(parts.front());
        out.beta_profile = std::move(beta_parts.front());
    } else if (q.want_profile) {
        out.sigma_t_profile = sumProfiles(parts);
        out.beta_profile = sumProfiles(beta_parts);
    }
    return out;
}

std::vector<ProfileSegment> sumProfiles(const std::vector<std::vector<ProfileSegment>>& parts)
{
    if (parts.size() == 1) return parts.front();
    std::vector<double> cuts;
    for (const auto& p : parts)
        for (const auto& s : p) {
            cuts.push_back(s.t0_m);
            cuts.push_back(s.t1_m);
        }
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
    std::vector<ProfileSegment> out;
    std::vector<size_t> idx(parts.size(), 0);
    for (size_t i = 0; i + 1 < cuts.size(); ++i) {
        const double a = cuts[i], b = cuts[i + 1], m = 0.5 * (a + b);
        double v = 0;
        for (size_t k = 0; k < parts.size(); ++k) {
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
    return out;
}

}  // namespace smokescan
