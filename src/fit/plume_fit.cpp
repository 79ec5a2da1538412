#include "smokescan/fit/plume_fit.hpp"

#include <algorithm>
#include <cmath>

#include <ceres/ceres.h>

#include "binomial_deviance.hpp"
#include "ceres_fit.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/order_stats.hpp"
#include "smokescan/sensor_config/laser_kind.hpp"

namespace smokescan {
namespace {

/// ln d_i − (ln D − k·x_i), x = ln(ρ/ρ_ref).
struct DepthResidual {
    double x, ln_d;
    template <typename T>
    bool operator()(const T* lnD_k, T* r) const
    {
        r[0] = T(ln_d) - (lnD_k[0] - lnD_k[1] * T(x));
        return true;
    }
};

/// The bin's echo share as a binomial count: p = 1/(1 + e^{−s·(x − x50)}), x = ln ρ. Signed
/// deviance residual (pearson = false), or the Pearson residual (share − p)/√(p̃(1 − p̃)/n) with p̃
/// fixed at the solution, for the covariance.
struct ShareResidual {
    double x, n, echo;
    bool pearson;
    double inv_sd;  ///< 1/√(p̃(1 − p̃)/n) (Pearson only)
    template <typename T>
    bool operator()(const T* x50_s, T* r) const
    {
        const T z = x50_s[1] * (T(x) - x50_s[0]);
        T p, q;
        detail::tails(z, /*logistic=*/true, p, q);
        if (pearson)
            r[0] = (T(echo / n) - p) * T(inv_sd);
        else
            r[0] = detail::signedDeviance(n, echo, p, q);
        return true;
    }
};

/// Each logged beam that crosses a plume at its scan's time: its peak density, where it enters
/// the plume, where the surface is, and what the Sick reported.
std::vector<PlumeObservation> observePlumes(const RecordedLog& log, const std::vector<SmokeVolume>& local,
                                            const SurfaceSet& surfaces, const SensorMount& mount, const LrfSpec& spec,
                                            const PlumeFitConfig& cfg)
{
    const double sigma_per_density = local.front().medium.sigmaT(spec.wavelength_nm);
    std::vector<PlumeObservation> obs;
    BeamQuery q;
    q.wavelength_nm = spec.wavelength_nm;
    q.want_profile = true;
    for (const LaserLogScan& s : log.scans) {
        const SmokeField field = SmokeField::at(local, s.time_s + cfg.time_offset_s);
        for (size_t i = 0; i < s.angle_rad.size(); ++i) {
            const double a = s.angle_rad[i];
            const Ray ray = mount.beamRay(a);
            const SurfaceHit h = surfaces.closest(ray, spec.range_max_m);
            const double L = h.endOr(spec.range_max_m);
            const BeamSmoke sm = field.trace(ray, 0.0, L, q);
            if (sm.sigma_t_profile.empty()) continue;
            double peak = 0;
            for (const auto& g : sm.sigma_t_profile) peak = std::max(peak, g.density);
            if (!(peak > 0)) continue;
            PlumeObservation o;
            o.time_s = s.time_s;
            o.angle_rad = a;
            o.peak_density = peak / sigma_per_density;
            o.surface_m = L;
            for (const auto& g : sm.sigma_t_profile)
                if (g.density >= cfg.entry_fraction * peak) {
                    o.entry_m = g.t0_m;
                    break;
                }
            const double m = s.range[i] * log.unit_m;
            if (spec.isErrorRange(m)) {
                o.outcome = PlumeObservation::ErrorValue;
            } else {
                o.range_m = m;
                o.outcome = m < L - cfg.surface_margin_m ? PlumeObservation::SmokeEcho : PlumeObservation::Surface;
            }
            obs.push_back(o);
        }
    }
    return obs;
}

/// Density bins (log-spaced over the observed range): outcomes and mean depth per bin. Returns
/// the densities of the smoke echoes.
std::vector<double> binObservations(PlumeFitResult& res, int bins)
{
    double lo = kInf, hi = 0;
    for (const auto& o : res.obs) {
        lo = std::min(lo, o.peak_density);
        hi = std::max(hi, o.peak_density);
    }
    const int B = std::max(1, bins);
    const double llo = std::log(lo), lhi = std::log(hi) + 1e-12;
    res.bins.resize(size_t(B));
    std::vector<std::vector<double>> depths(static_cast<size_t>(B));
    for (int b = 0; b < B; ++b) {
        res.bins[size_t(b)].rho_lo = std::exp(llo + (lhi - llo) * b / B);
        res.bins[size_t(b)].rho_hi = std::exp(llo + (lhi - llo) * (b + 1) / B);
    }
    std::vector<double> echo_rho;
    for (const auto& o : res.obs) {
        const int b = std::clamp(int((std::log(o.peak_density) - llo) / (lhi - llo) * B), 0, B - 1);
        auto& bin = res.bins[size_t(b)];
        ++bin.n;
        if (o.outcome == PlumeObservation::SmokeEcho) {
            ++bin.echo;
            depths[size_t(b)].push_back(o.range_m - o.entry_m);
            echo_rho.push_back(o.peak_density);
        } else if (o.outcome == PlumeObservation::Surface) {
            ++bin.surface;
        } else {
            ++bin.error;
        }
    }
    for (int b = 0; b < B; ++b) {
        const auto& d = depths[size_t(b)];
        if (d.empty()) continue;
        double m = 0, v = 0;
        for (double x : d) m += x / double(d.size());
        for (double x : d) v += (x - m) * (x - m);
        res.bins[size_t(b)].mean_depth_m = m;
        res.bins[size_t(b)].se_depth_m = d.size() > 1 ? std::sqrt(v / double(d.size() - 1) / double(d.size())) : NAN;
    }
    return echo_rho;
}

/// Depth against density: ln d = ln D − k·ln(ρ/ρ_ref), least squares, errors scaled by the scatter.
void fitDepth(PlumeFitResult& res, size_t echoes, const PlumeFitConfig& cfg)
{
    double lnD_k[2] = {std::log(std::max(cfg.min_depth_m, 0.1)), 0.5};
    ceres::Problem problem;
    for (const auto& o : res.obs)
        if (o.outcome == PlumeObservation::SmokeEcho)
            problem.AddResidualBlock(new ceres::AutoDiffCostFunction<DepthResidual, 1, 2>(
                                         new DepthResidual{std::log(o.peak_density / res.rho_ref),
                                                           std::log(std::max(cfg.min_depth_m, o.range_m - o.entry_m))}),
                                     nullptr, lnD_k);
    ceres::Solver::Options opt;
    opt.linear_solver_type = ceres::DENSE_QR;
    ceres::Solver::Summary sum;
    detail::solveQuiet(problem, opt, sum);
    res.depth_chi2 = 2 * sum.final_cost;
    res.depth_dof = int(echoes) - 2;
    double C[4];
    if (res.depth_dof > 0 && detail::blockCovariance(problem, lnD_k, C)) {
        const double s2 = res.depth_chi2 / res.depth_dof;  // unknown scatter: scale by the residuals'
        const double D = std::exp(lnD_k[0]);
        res.depth_m = {D, D * std::sqrt(C[0] * s2)};
        res.exponent = {lnD_k[1], std::sqrt(C[3] * s2)};
        res.cov_lnD_k = C[1] * s2;
        res.ok = true;
    } else {
        res.diagnoses.push_back("the depth fit's covariance could not be computed");
    }
}

/// Share of beams that echo from the plume against ln ρ: maximum likelihood over the bins; the
/// covariance from the Fisher information at the solution (Pearson residuals, variances at the
/// fitted shares), inflated by the bins' over-dispersion.
void fitEchoShare(PlumeFitResult& res)
{
    std::vector<const PlumeFitResult::Bin*> used;
    for (const auto& b : res.bins)
        if (b.n > 0) used.push_back(&b);
    if (used.size() < 3) return;
    double xs[2] = {std::log(res.rho_ref), 2.0};
    auto xOf = [](const PlumeFitResult::Bin* b) { return 0.5 * (std::log(b->rho_lo) + std::log(b->rho_hi)); };
    ceres::Problem ml;
    for (const auto* b : used)
        ml.AddResidualBlock(new ceres::AutoDiffCostFunction<ShareResidual, 1, 2>(
                                new ShareResidual{xOf(b), double(b->n), double(b->echo), false, 0.0}),
                            nullptr, xs);
    ceres::Solver::Options opt;
    opt.linear_solver_type = ceres::DENSE_QR;
    opt.max_num_iterations = 200;
    ceres::Solver::Summary sum;
    const bool settled = detail::solveQuiet(ml, opt, sum);
    ceres::Problem problem;
    for (const auto* b : used) {
        const double x = xOf(b);
        const double p0 = std::clamp(1.0 / (1.0 + std::exp(-xs[1] * (x - xs[0]))), 0.02, 0.98);
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ShareResidual, 1, 2>(new ShareResidual{
                                     x, double(b->n), double(b->echo), true, 1.0 / std::sqrt(p0 * (1 - p0) / b->n)}),
                                 nullptr, xs);
    }
    double cost = 0;
    problem.Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr, nullptr, nullptr);
    res.share_chi2 = 2 * cost;
    res.share_dof = int(used.size()) - 2;
    double C[4];
    if (settled && detail::blockCovariance(problem, xs, C)) {
        const double infl = std::max(1.0, res.share_dof > 0 ? res.share_chi2 / res.share_dof : 1.0);
        const double r50 = std::exp(xs[0]);
        res.rho_50 = {r50, r50 * std::sqrt(C[0] * infl)};
        res.slope = {xs[1], std::sqrt(C[3] * infl)};
    }
    if (!settled) res.diagnoses.push_back("the echo share fit did not settle");
}

}  // namespace

PlumeFitResult fitSickPlume(const RecordedLog& log, const Scene& scene, const SurfaceSet& surfaces,
                            const SensorMount& mount, const PlumeFitConfig& cfg)
{
    const LrfSpec spec = specFor(mount.config);
    if (!laserKind(spec.type).fitsPlume())
        throw Error(
            "fit-plume",
            "the plume fit is for the Sick LMS200; sensor '" + mount.name + "' is a " + sensorTypeName(spec.type));
    std::vector<SmokeVolume> local;
    for (const auto& v : scene.volumes)
        if (v.role == SmokeRole::Local) local.push_back(v);
    if (local.empty()) throw Error(scene.source, "has no local smoke (plumes) for the Sick to see");
    PlumeFitResult res;
    res.obs = observePlumes(log, local, surfaces, mount, spec, cfg);
    if (res.obs.empty()) {
        res.diagnoses.push_back(
            "no beam of the log crosses the scene's plumes (check the sensor, the times and --time-offset)");
        return res;
    }
    const std::vector<double> echo_rho = binObservations(res, cfg.bins);
    if (echo_rho.size() < 3) {
        res.diagnoses.push_back("fewer than 3 smoke echoes: the Sick saw through or lost every plume");
        return res;
    }
    res.rho_ref = median(echo_rho);
    fitDepth(res, echo_rho.size(), cfg);
    fitEchoShare(res);
    return res;
}

Estimate plumeDepthAt(const PlumeFitResult& r, double rho)
{
    if (!r.ok || !(rho > 0)) return {};
    const double x = std::log(rho / r.rho_ref), rel_D = r.depth_m.se / r.depth_m.value;
    const double var = rel_D * rel_D + x * x * r.exponent.se * r.exponent.se - 2 * x * r.cov_lnD_k;
    const double d = r.depth_m.value * std::exp(-r.exponent.value * x);
    return {d, d * std::sqrt(std::max(0.0, var))};
}

}  // namespace smokescan
