#include "smokescan/media/timeline.hpp"

#include <algorithm>
#include <cmath>

#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"

namespace smokescan {

DensityTimeline DensityTimeline::constant(double value)
{
    if (!(value >= 0) || !std::isfinite(value)) throw Error("", "density scale must be finite and >= 0");
    DensityTimeline t;
    t.value_ = value;
    return t;
}

DensityTimeline DensityTimeline::keyframes(std::vector<std::pair<double, double>> keys, Interp interp, double decay_s)
{
    if (keys.empty()) throw Error("", "keyframes need at least one (time, value) pair");
    for (size_t i = 0; i < keys.size(); ++i) {
        const auto [t, v] = keys[i];
        if (!std::isfinite(t) || !std::isfinite(v) || v < 0)
            throw Error("", "keyframe " + std::to_string(i) + " must have a finite time and a finite value >= 0");
        if (i > 0 && !(t > keys[i - 1].first))
            throw Error("", "keyframe times must increase strictly (key " + std::to_string(i) + ")");
        if (interp == Interp::Exp && v <= 0)
            throw Error("", "exp keyframes need values > 0 (key " + std::to_string(i) + ")");
    }
    if (!(decay_s >= 0) || !std::isfinite(decay_s)) throw Error("", "decay_s must be finite and >= 0");
    DensityTimeline t;
    t.kind_ = Kind::Keyframes;
    t.pts_ = std::move(keys);
    t.interp_ = interp;
    t.decay_s_ = decay_s;
    return t;
}

DensityTimeline DensityTimeline::machine(std::vector<std::pair<double, double>> on_s, double fill_per_s,
                                         double dissolve_s)
{
    if (!(fill_per_s > 0) || !std::isfinite(fill_per_s)) throw Error("", "fill_per_s must be finite and > 0");
    if (!(dissolve_s > 0) || !std::isfinite(dissolve_s)) throw Error("", "dissolve_s must be finite and > 0");
    for (size_t i = 0; i < on_s.size(); ++i) {
        if (!std::isfinite(on_s[i].first) || !(on_s[i].second > on_s[i].first))
            throw Error("", "machine interval " + std::to_string(i) + " must have finite start < end");
        if (i > 0 && on_s[i].first < on_s[i - 1].second)
            throw Error("", "machine intervals must be in order and not overlap (interval " + std::to_string(i) + ")");
    }
    double on_time_s = 0;
    for (const auto& [a, b] : on_s) on_time_s += b - a;
    if (!(fill_per_s * std::min(on_time_s, 10 * dissolve_s) <= limits::kDensity))
        throw Error("", "fill_per_s × time on reaches a density factor over " + std::to_string(limits::kDensity));
    DensityTimeline t;
    t.kind_ = Kind::Machine;
    t.pts_ = std::move(on_s);
    t.fill_ = fill_per_s;
    t.dissolve_s_ = dissolve_s;
    return t;
}

double DensityTimeline::at(double t) const { return scale_ * base(t); }

DensityTimeline DensityTimeline::scaled(double k) const
{
    if (!(k >= 0) || !std::isfinite(k)) throw Error("smoke scale", "must be finite and >= 0");
    DensityTimeline out = *this;
    out.scale_ *= k;
    return out;
}

double DensityTimeline::base(double t) const
{
    switch (kind_) {
    case Kind::Constant:
        return value_;
    case Kind::Machine: {
        // Each interval [a, b] contributes ∫_a^{min(t,b)} q·e^{−(t−s)/τ} ds.
        double rho = 0;
        for (const auto& [a, b] : pts_) {
            if (t <= a) break;
            const double e = std::min(t, b);
            rho += fill_ * dissolve_s_ * (std::exp(-(t - e) / dissolve_s_) - std::exp(-(t - a) / dissolve_s_));
        }
        return rho;
    }
    case Kind::Keyframes:
        break;
    }
    if (t <= pts_.front().first) return pts_.front().second;
    if (t >= pts_.back().first) {
        const double v = pts_.back().second;
        return decay_s_ > 0 ? v * std::exp(-(t - pts_.back().first) / decay_s_) : v;
    }
    const auto it = std::upper_bound(pts_.begin(), pts_.end(), t,
                                     [](double x, const std::pair<double, double>& p) { return x < p.first; });
    const auto& [t1, v1] = *it;
    const auto& [t0, v0] = *(it - 1);
    const double f = (t - t0) / (t1 - t0);
    switch (interp_) {
    case Interp::Step:
        return v0;
    case Interp::Exp:
        return v0 * std::pow(v1 / v0, f);
    default:
        return v0 + f * (v1 - v0);
    }
}

}  // namespace smokescan
