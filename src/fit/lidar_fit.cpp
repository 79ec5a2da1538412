// A 3D lidar's surfaces' reflectance factors from its recorded intensities (fit/lidar_fit.hpp).
#include "smokescan/fit/lidar_fit.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "ceres_fit.hpp"
#include "intensity_ratio_residual.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/core/order_stats.hpp"

namespace smokescan {
namespace {

/// The recorded intensity brought to the replay's range: the recorded peak in the replay's units.
double recordedPeak(const LidarIntensitySample& x)
{
    const double r = x.recorded_range_m > 0 ? double(x.range_m) / double(x.recorded_range_m) : 1.0;
    return double(x.recorded) * r * r;
}

/// The replay's intensity at factor k, and its peak in noise sd.
double meanAt(const LidarIntensitySample& x, double k) { return double(x.expected) * x.scaleAt(k); }
double peakSdAt(const LidarIntensitySample& x, double k) { return double(x.peak_sd) * x.scaleAt(k); }

/// The peak's noise sd in intensity, and the recorded value's rounding to `quantum` (0: none).
double intensityNoise(const LidarIntensitySample& x, double quantum)
{
    return std::hypot(double(x.expected) * double(x.peak_noise) / double(x.peak_sd), quantum / std::sqrt(12.0));
}

/// The lesser of g's slopes at ¼ and at 1 (LidarIntensitySample::scaleAt, by its tangents beyond
/// the ends): the peak's share that scales with the surface's power.
double slope(const LidarIntensitySample& x)
{
    return std::min(x.scaleAt(2.0) - 1.0, double(x.at_quarter) - x.scaleAt(-0.75));
}

/// One surface's factor on its beams.
struct FactorFit {
    double k = 1;
    double unit_var = NAN;  ///< (JᵀJ)⁻¹: k's variance per unit residual variance
    double ss = 0;  ///< the residuals' sum of squares
    double scatter(size_t n) const { return std::sqrt(ss / double(n - 1)); }  ///< rms residual
};

FactorFit fitFactor(const std::vector<LidarIntensitySample>& s, const std::vector<size_t>& beams, double k0,
                    double quantum)
{
    FactorFit f;
    f.k = k0;
    ceres::Problem problem;
    for (size_t i : beams)
        problem.AddResidualBlock(
            new ceres::AutoDiffCostFunction<detail::IntensityRatioResidual, 1, 1>(
                new detail::IntensityRatioResidual(recordedPeak(s[i]), s[i], intensityNoise(s[i], quantum))),
            nullptr, &f.k);
    ceres::Solver::Summary summary;
    detail::solveQuiet(problem, detail::denseOptions(50, 1e-12), summary);
    f.ss = 2 * summary.final_cost;
    if (!detail::blockCovariance(problem, &f.k, &f.unit_var)) f.unit_var = NAN;
    return f;
}

/// The beams of a surface usable at factor k: bright enough, mostly the surface's, under the
/// cap, and within clip_sd of the residuals' robust sd (1.4826·MAD: a few echoes far off cannot
/// widen the clip that is to remove them).
std::vector<size_t> usable(const std::vector<LidarIntensitySample>& s, const std::vector<size_t>& beams, double k,
                           double quantum, const LidarFitConfig& cfg)
{
    std::vector<size_t> u;
    std::vector<double> r;
    for (size_t i : beams) {
        if (slope(s[i]) < cfg.min_slope || peakSdAt(s[i], k) < cfg.min_peak_sd || meanAt(s[i], k) > cfg.max_intensity)
            continue;
        u.push_back(i);
        r.push_back((recordedPeak(s[i]) - meanAt(s[i], k)) / intensityNoise(s[i], quantum));
    }
    if (u.empty()) return u;
    const double mid = median(r);
    std::vector<double> dev(r.size());
    std::transform(r.begin(), r.end(), dev.begin(), [&](double x) { return std::abs(x - mid); });
    const double clip = cfg.clip_sd * 1.4826 * median(std::move(dev));
    std::vector<size_t> kept;
    for (size_t j = 0; j < u.size(); ++j)
        if (std::abs(r[j] - mid) <= clip) kept.push_back(u[j]);
    return kept;
}

}  // namespace

LidarFitResult fitLidarIntensities(const std::vector<LidarIntensitySample>& samples, const LidarFitConfig& cfg)
{
    std::map<int, std::vector<size_t>> by_surface;
    for (size_t i = 0; i < samples.size(); ++i) {
        const LidarIntensitySample& x = samples[i];
        if (x.surface >= 0 && x.expected > 0 && x.peak_sd > 0 && x.peak_noise > 0 && std::isfinite(x.recorded) &&
            x.recorded > 0 && x.at_half > 0 && x.at_quarter > 0)
            by_surface[x.surface].push_back(i);
    }
    LidarFitResult out;
    out.quantum = 1;
    for (const auto& [surface, beams] : by_surface)
        for (size_t i : beams)
            if (samples[i].recorded != std::round(samples[i].recorded)) out.quantum = 0;
    const double quantum = out.quantum;
    double ss_all = 0;
    long long fitted = 0;
    for (const auto& [surface, beams] : by_surface) {
        // The usable beams at the current fit, then the fit on them (their noise at the factor
        // before), until neither the beams nor the factor move.
        SurfaceReflectanceFit r;
        r.surface = surface;
        r.candidates = (long long)beams.size();
        std::vector<size_t> used;
        FactorFit fit;
        bool have = false;
        for (int round = 0; round < 20; ++round) {
            std::vector<size_t> now = usable(samples, beams, have ? fit.k : 1.0, quantum, cfg);
            if ((long long)now.size() < cfg.min_beams) {
                have = false;
                break;
            }
            const double before = fit.k;
            const bool same = have && now == used;
            used = std::move(now);
            fit = fitFactor(samples, used, have ? fit.k : 1.0, quantum);
            const double step = std::abs(fit.k - before) / std::sqrt(fit.unit_var * fit.ss / double(used.size() - 1));
            have = std::isfinite(fit.unit_var);
            out.rounds = std::max(out.rounds, round + 1);
            if (!have || (same && step < 1e-3)) break;
        }
        if (have && fit.k > 0) {
            r.beams = (long long)used.size();
            r.factor = fit.k;
            r.scatter = fit.scatter(used.size());
            // Its own residuals' variance, not the pooled one: a surface the factor fits less well
            // (an angle dependence that is not Lambertian) carries its own larger error.
            r.factor_se = std::sqrt(fit.unit_var) * r.scatter;
            r.factor_sys = kIntensitySystematic * r.factor;
            r.fitted = true;
            ss_all += fit.ss, out.beams += r.beams, ++fitted;
        }
        out.surfaces.push_back(r);
    }
    if (fitted == 0)
        throw Error("lidar fit",
                    fmt("no surface has %lld answered beams the replay is sure of whose echo peaks %g noise sd at "
                        "least: are the frames' intensities the sensor's calibrated reflectivity [%%], and enough?",
                        cfg.min_beams, cfg.min_peak_sd));
    out.scatter = std::sqrt(ss_all / double(out.beams - fitted));
    out.scatter_se = out.scatter / std::sqrt(2.0 * double(out.beams - fitted));
    return out;
}

}  // namespace smokescan
