#include "render_medium.hpp"

#include <algorithm>
#include <cmath>

namespace smokescan {

RenderMedium::RenderMedium(const SmokeField& field, int cells)
{
    for (const auto& e : field.entries()) {
        Component c;
        c.grid = e.grid;
        c.scale = e.scale;
        for (int k = 0; k < 3; ++k) c.sigma_t[k] = e.volume->medium.sigmaT(kRgbWavelengths[k]);
        c.albedo = e.volume->medium.albedo;
        c.g = e.volume->medium.g;
        comps_.push_back(c);
    }
    build(cells);
}

RenderMedium::RenderMedium(std::vector<Component> comps, int cells) : comps_(std::move(comps)) { build(cells); }

double RenderMedium::density(const Component& c, const Vec3& p)
{
    if (c.grid) return c.grid->sample(p);
    return (p.array() >= c.box.lo.array()).all() && (p.array() < c.box.hi.array()).all() ? 1.0 : 0.0;
}

namespace {
/// Density range of an analytic unit box over a cell: exact.
void boxRange(const Aabb& box, const Aabb& cell, double& mn, double& mx)
{
    const bool inside = (cell.lo.array() >= box.lo.array()).all() && (cell.hi.array() <= box.hi.array()).all();
    const bool meets = (cell.hi.array() > box.lo.array()).all() && (cell.lo.array() < box.hi.array()).all();
    mn = inside ? 1.0 : 0.0;
    mx = meets ? 1.0 : 0.0;
}
}  // namespace

void RenderMedium::build(int cells)
{
    std::vector<std::vector<std::pair<Aabb, double>>> blocks;
    for (const auto& c : comps_) {
        blocks.push_back(c.grid ? c.grid->blockMaxima() : std::vector<std::pair<Aabb, double>>{{c.box, 1.0}});
        for (const auto& [b, m] : blocks.back()) {
            bounds_.extend(b.lo);
            bounds_.extend(b.hi);
        }
    }
    if (bounds_.empty()) {
        comps_.clear();
        return;
    }
    // Pad by a hair so that points on the outer faces fall inside.
    const Vec3 ext = (bounds_.hi - bounds_.lo).cwiseMax(1e-6);
    bounds_.lo -= 1e-6 * ext;
    bounds_.hi += 1e-6 * ext;
    const double cell = (bounds_.hi - bounds_.lo).maxCoeff() / std::max(1, cells);
    for (int a = 0; a < 3; ++a) {
        n_[a] = std::max(1, int(std::ceil((bounds_.hi[a] - bounds_.lo[a]) / cell)));
        cell_m_[a] = (bounds_.hi[a] - bounds_.lo[a]) / n_[a];
    }
    cells_.assign(size_t(n_[0]) * n_[1] * n_[2], Cell{});
    std::vector<float> one(cells_.size());
    for (size_t k = 0; k < comps_.size(); ++k) {
        const Component& comp = comps_[k];
        std::fill(one.begin(), one.end(), 0.0f);
        const double smax = comp.scale * comp.sigma_t.maxCoeff();
        Aabb cb;  // this component's bounds
        for (const auto& [b, m] : blocks[k]) {
            cb.extend(b.lo);
            cb.extend(b.hi);
            int lo[3], hi[3];
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::clamp(int(std::floor((b.lo[a] - bounds_.lo[a]) / cell_m_[a])), 0, n_[a] - 1);
                hi[a] = std::clamp(int(std::floor((b.hi[a] - bounds_.lo[a]) / cell_m_[a])), 0, n_[a] - 1);
            }
            const float v = float(m);
            for (int z = lo[2]; z <= hi[2]; ++z)
                for (int y = lo[1]; y <= hi[1]; ++y)
                    for (int x = lo[0]; x <= hi[0]; ++x) {
                        float& o = one[(size_t(z) * n_[1] + y) * n_[0] + x];
                        o = std::max(o, v);
                    }
        }
        // Per cell: exact density range where the grid can give it cheaply, else [0, block max].
        for (int z = 0; z < n_[2]; ++z)
            for (int y = 0; y < n_[1]; ++y)
                for (int x = 0; x < n_[0]; ++x) {
                    const size_t i = (size_t(z) * n_[1] + y) * n_[0] + x;
                    if (one[i] <= 0) continue;
                    Aabb box;
                    box.lo = bounds_.lo + Vec3(x, y, z).cwiseProduct(cell_m_);
                    box.hi = box.lo + cell_m_;
                    double mn = 0, mx = one[i];
                    if (!comp.grid)
                        boxRange(comp.box, box, mn, mx);
                    else if (comp.grid->rangeIn(box, mn, mx))
                        mx = std::min<double>(mx, one[i]);
                    Cell& c = cells_[i];
                    // Floats must not round below the true bound: a relative hair of headroom.
                    c.mu += float(mx * smax) * (1.0f + 1e-6f);
                    c.mu_r += float((mx - mn) * smax) * (1.0f + 1e-6f);
                    for (int ch = 0; ch < 3; ++ch) c.ctrl[ch] += float(mn * comp.scale * comp.sigma_t[ch]);
                }
    }
}

void RenderMedium::coefficients(const Vec3& p, Rgb& sigma_t, Rgb& sigma_s) const
{
    sigma_t.setZero();
    sigma_s.setZero();
    for (const auto& c : comps_) {
        const double rho = density(c, p) * c.scale;
        if (rho <= 0) continue;
        sigma_t += rho * c.sigma_t;
        sigma_s += rho * c.albedo * c.sigma_t;
    }
}

MediumEvent RenderMedium::sample(const Ray& ray, double t_max, Rgb& beta, KeyedRng& rng) const
{
    MediumEvent ev;
    walkMajorant(ray, t_max, [&](double t0, double t1, const Cell& cell) {
        const double mu = cell.mu;
        if (mu <= 0) return false;
        double t = t0;
        for (;;) {
            t -= std::log(1.0 - rng.uniform()) / mu;
            if (t >= t1) return false;  // memoryless: restart at the next cell
            Rgb st, ss;
            coefficients(ray.at(t), st, ss);
            const Rgb sa = st - ss, sn = Rgb::Constant(mu) - st;
            const double pa = (beta * sa).abs().mean(), ps = (beta * ss).abs().mean(), pn = (beta * sn).abs().mean();
            const double sum = pa + ps + pn;
            if (!(sum > 0)) {
                ev.kind = MediumEvent::Absorb;  // zero throughput: nothing more to carry
                return true;
            }
            const double u = rng.uniform() * sum;
            if (u < pa) {
                ev.kind = MediumEvent::Absorb;
                ev.t = t;
                return true;
            }
            if (u < pa + ps) {
                ev.kind = MediumEvent::Scatter;
                ev.t = t;
                if (comps_.size() == 1) {
                    beta *= ss / (mu * ps / sum);
                    ev.g = comps_[0].g;
                    return true;
                }
                // Which component scattered sets the phase function. Picked by its share of the
                // channel-mean σ_s, and weighted by its own σ_s per channel over that probability,
                // so that each channel gets its own mix of phase functions (volumes whose spectral
                // slopes differ give each channel a different mix).
                const double pick = rng.uniform() * ss.mean();
                double acc = 0;
                bool chosen = false;
                Rgb sk = Rgb::Zero();  // the chosen component's σ_s (the last one, if rounding runs past)
                forEachScatterer(ray.at(t), [&](const Rgb& s_k, double g) {
                    if (chosen) return;
                    acc += s_k.mean();
                    sk = s_k;
                    ev.g = g;
                    chosen = pick < acc;
                });
                const double q = sk.mean() / ss.mean();
                if (!(q > 0)) {  // nothing scattered here
                    ev.kind = MediumEvent::Absorb;
                    return true;
                }
                beta *= sk / (q * mu * ps / sum);
                return true;
            }
            beta *= sn / (mu * pn / sum);  // null collision
        }
    });
    return ev;
}

Rgb RenderMedium::transmittance(const Ray& ray, double t_max, KeyedRng& rng) const
{
    Rgb ratio = Rgb::Ones(), tau_ctrl = Rgb::Zero();  // T = e^{−τ_c} · Π(1 − (σ_t − σ_c)/μ̄_r)
    walkMajorant(ray, t_max, [&](double t0, double t1, const Cell& cell) {
        const Rgb ctrl(cell.ctrl[0], cell.ctrl[1], cell.ctrl[2]);
        tau_ctrl += ctrl * (t1 - t0);
        const double mu_r = cell.mu_r;
        if (mu_r > 0) {
            for (double t = t0;;) {
                t -= std::log(1.0 - rng.uniform()) / mu_r;
                if (t >= t1) break;
                Rgb st, ss;
                coefficients(ray.at(t), st, ss);
                ratio *= Rgb::Ones() - (st - ctrl) / mu_r;
            }
        }
        return (tau_ctrl > 40.0).all() || (ratio == 0.0).all();  // nothing left (e^{−40} ≈ 4e−18)
    });
    return ratio * (-tau_ctrl).exp();
}

namespace {
/// Optical depth of the majorant over [0, t_max) and, at t (when t < t_max), the majorant there
/// and its optical depth up to t.
struct MajorantDepth {
    double total = 0, before_t = 0, mu_t = 0;
};
}  // namespace

bool RenderMedium::sampleForced(const Ray& ray, double t_max, double u, double& t, double& pdf) const
{
    double total = 0;
    walkMajorant(ray, t_max, [&](double t0, double t1, const Cell& c) {
        total += double(c.mu) * (t1 - t0);
        return false;
    });
    if (!(total > 0)) return false;
    // τ* from the truncated exponential: 1 − e^{−τ*} = u·(1 − e^{−τ̄}).
    const double norm = -std::expm1(-total);
    const double target = std::min(total, -std::log1p(-u * norm));
    double acc = 0;
    bool found = false;
    walkMajorant(ray, t_max, [&](double t0, double t1, const Cell& c) {
        const double d = double(c.mu) * (t1 - t0);
        if (c.mu > 0 && (acc + d >= target || t1 >= t_max)) {
            t = std::min(t1, t0 + (target - acc) / double(c.mu));
            pdf = double(c.mu) * std::exp(-std::min(target, acc + d)) / norm;
            found = true;
            return true;
        }
        acc += d;
        return false;
    });
    return found && t < t_max && pdf > 0;
}

double RenderMedium::forcedPdf(const Ray& ray, double t_max, double t) const
{
    MajorantDepth m;
    walkMajorant(ray, t_max, [&](double t0, double t1, const Cell& c) {
        const double mu = c.mu;
        if (t >= t0 && t < t1) {
            m.mu_t = mu;
            m.before_t = m.total + mu * (t - t0);
        }
        m.total += mu * (t1 - t0);
        return false;
    });
    if (!(m.total > 0) || !(m.mu_t > 0)) return 0;
    return m.mu_t * std::exp(-m.before_t) / -std::expm1(-m.total);
}

}  // namespace smokescan
