#include "smokescan/fit/physical_fit.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

#include <ceres/ceres.h>

#include "binomial_deviance.hpp"
#include "ceres_fit.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/sensor_config/laser_kind.hpp"
#include "smokescan/sensors/physical_model.hpp"

namespace smokescan {
namespace {

/// Noise-free amplitudes of each beam over a density grid, interpolated in log amplitude (they
/// fall as e^{−2σ_t·ρ·L}).
struct AmplitudeTable {
    double rho_max = 0;
    int n = 0;
    std::vector<std::vector<AmcwAmplitudes>> beam;  ///< [beam][grid point]

    AmcwAmplitudes at(size_t b, double rho) const
    {
        const double x = std::clamp(rho / rho_max, 0.0, 1.0) * (n - 1);
        const int j = std::min(n - 2, int(x));
        const double f = x - j;
        const AmcwAmplitudes &a = beam[b][size_t(j)], &c = beam[b][size_t(j + 1)];
        auto lerp = [f](double u, double v) {
            return (u > 0 && v > 0) ? std::exp((1 - f) * std::log(u) + f * std::log(v)) : (1 - f) * u + f * v;
        };
        return {lerp(a.lo, c.lo), lerp(a.hi, c.hi)};
    }
};

struct Obs {
    double rho = 0;
    int n = 0, e = 0, block = 0;
};

/// Mean error probability of the group's beams at density rho for noise floor exp(theta).
double groupErrorProbability(const AmplitudeTable& tab, PhysicalParams p, double theta, double rho)
{
    p.noise_floor = std::exp(theta);
    double sum = 0;
    for (size_t b = 0; b < tab.beam.size(); ++b) sum += amcwErrorProbability(p, tab.at(b, rho));
    return sum / double(tab.beam.size());
}

/// The group's error probability on the density grid for noise floor exp(theta); observations
/// interpolate it (the grid is much finer than p changes).
std::vector<double> probabilityTable(const AmplitudeTable& tab, const PhysicalParams& p, double theta)
{
    std::vector<double> out(size_t(tab.n));
    for (int j = 0; j < tab.n; ++j)
        out[size_t(j)] = groupErrorProbability(tab, p, theta, tab.rho_max * j / (tab.n - 1));
    return out;
}

double interpolateTable(const AmplitudeTable& tab, const std::vector<double>& P, double rho)
{
    const double x = std::clamp(rho / tab.rho_max, 0.0, 1.0) * (tab.n - 1);
    const int j = std::min(tab.n - 2, int(x));
    return P[size_t(j)] + (x - j) * (P[size_t(j) + 1] - P[size_t(j)]);
}

/// Error probability of each observation for noise floor exp(θ).
std::vector<double> observationProbabilities(const AmplitudeTable& tab, const PhysicalParams& p,
                                             const std::vector<Obs>& obs, double theta)
{
    const std::vector<double> P = probabilityTable(tab, p, theta);
    std::vector<double> out(obs.size());
    for (size_t k = 0; k < obs.size(); ++k) out[k] = interpolateTable(tab, P, obs[k].rho);
    return out;
}

/// Residuals r_k(θ) of all scans in θ = ln σ, from each scan's error probability; the Jacobian by
/// central differences of the whole residual (the probability table is not differentiable
/// symbolically).
class ScanResiduals : public ceres::CostFunction {
public:
    /// residual(k, p) for observation k at error probability p
    using Residual = std::function<double(size_t, double)>;
    ScanResiduals(const AmplitudeTable& tab, const PhysicalParams& p, const std::vector<Obs>& obs, Residual res)
        : tab_(tab), p_(p), obs_(obs), res_(std::move(res))
    {
        set_num_residuals(int(obs.size()));
        mutable_parameter_block_sizes()->push_back(1);
    }
    bool Evaluate(double const* const* x, double* r, double** J) const override
    {
        const double theta = x[0][0], h = 1e-4;
        const std::vector<double> P = observationProbabilities(tab_, p_, obs_, theta);
        for (size_t k = 0; k < obs_.size(); ++k) r[k] = res_(k, P[k]);
        if (J && J[0]) {
            const std::vector<double> Pa = observationProbabilities(tab_, p_, obs_, theta + h);
            const std::vector<double> Pb = observationProbabilities(tab_, p_, obs_, theta - h);
            for (size_t k = 0; k < obs_.size(); ++k) J[0][k] = (res_(k, Pa[k]) - res_(k, Pb[k])) / (2 * h);
        }
        return true;
    }

private:
    const AmplitudeTable& tab_;
    const PhysicalParams& p_;
    const std::vector<Obs>& obs_;
    Residual res_;
};

struct ThetaFit {
    double theta = NAN, var_model = NAN, var_robust = NAN, chi2 = 0;
    bool ok = false;
};

/// Maximum likelihood for θ: Levenberg–Marquardt on the scans' signed deviance residuals. The
/// covariance comes from Pearson residuals with their variances at the solution (their JᵀJ is the
/// Fisher information), cluster-robust over the observations' blocks.
ThetaFit fitTheta(const AmplitudeTable& tab, const PhysicalParams& p, const std::vector<Obs>& obs, int iterations)
{
    ThetaFit out;
    // Start: the noise floor whose expected error count matches the observed one (monotone).
    double E = 0;
    for (const Obs& o : obs) E += o.e;
    auto expected = [&](double th) {
        double s = 0;
        const std::vector<double> P = observationProbabilities(tab, p, obs, th);
        for (size_t k = 0; k < obs.size(); ++k) s += obs[k].n * P[k];
        return s;
    };
    double lo = std::log(1e-9), hi = std::log(1e2);
    for (int it = 0; it < 40; ++it) {
        const double mid = 0.5 * (lo + hi);
        (expected(mid) < E ? lo : hi) = mid;
    }
    double theta = 0.5 * (lo + hi);
    auto clampP = [](double q) { return std::clamp(q, 1e-12, 1 - 1e-12); };
    ceres::Problem ml;
    ml.AddResidualBlock(new ScanResiduals(tab, p, obs,
                                          [&obs, clampP](size_t k, double pk) {
                                              const double q = clampP(pk);
                                              return detail::signedDeviance(double(obs[k].n), double(obs[k].e), q,
                                                                            1 - q);
                                          }),
                        nullptr, &theta);
    ceres::Solver::Options opt;
    opt.linear_solver_type = ceres::DENSE_QR;
    opt.max_num_iterations = iterations;
    opt.function_tolerance = 1e-12;
    opt.parameter_tolerance = 1e-10;
    ceres::Solver::Summary summary;
    if (!detail::solveQuiet(ml, opt, summary)) return out;

    const std::vector<double> P = observationProbabilities(tab, p, obs, theta);
    std::vector<double> inv_sd(obs.size());
    for (size_t k = 0; k < obs.size(); ++k) {
        const double pk = std::clamp(P[k], 1e-4, 1 - 1e-4);
        inv_sd[k] = 1 / std::sqrt(obs[k].n * pk * (1 - pk));
    }
    ceres::Problem problem;
    problem.AddResidualBlock(
        new ScanResiduals(tab, p, obs,
                          [&obs, inv_sd](size_t k, double pk) { return (obs[k].e - obs[k].n * pk) * inv_sd[k]; }),
        nullptr, &theta);
    // The Fisher information and the sandwich over the observations' time blocks.
    double cost = 0;
    problem.Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr, nullptr, nullptr);
    out.chi2 = 2 * cost;
    std::vector<long long> block_of;
    for (const Obs& o : obs) block_of.push_back(o.block);
    const detail::ClusterCovariance cc =
        detail::clusterRobustCovariance(problem, {&theta}, block_of, detail::ClusterCount::Informative);
    out.var_model = cc.model(0, 0);
    out.var_robust = cc.robust(0, 0);
    out.theta = theta;
    out.ok = std::isfinite(theta) && out.var_model > 0;
    return out;
}

}  // namespace

namespace {

/// The group's beams in the scene: their rays and the distances to their surfaces.
struct GroupBeams {
    std::vector<Ray> rays;
    std::vector<double> L;  ///< [m]
};

GroupBeams groupBeams(const SurfaceSet& surfaces, const SensorMount& mount, const LrfSpec& spec, const BeamGroup& group)
{
    GroupBeams gb;
    for (int i = 0; i < spec.n_beams; ++i)
        if (group.contains(spec.angle(i))) {
            gb.rays.push_back(mount.beamRay(spec.angle(i)));
            gb.L.push_back(surfaces.closest(gb.rays.back(), spec.range_max_m).endOr(spec.range_max_m));
        }
    return gb;
}

/// Observations: each aligned scan's density from its saturation, its beams and errors on the
/// group, and its time block (the clusters of the covariance).
std::vector<Obs> densityObservations(const SensorFitResult& fit, size_t g, const CurveFitResult& calib, double block_s)
{
    std::vector<Obs> obs;
    double t_block0 = NAN;
    for (const AlignedScan& a : fit.aligned) {
        if (!std::isfinite(a.saturation) || a.beams[g] == 0) continue;
        double rho = 0;
        if (a.saturation < calib.curve.S0) {
            try {
                rho = calib.curve.invert(a.saturation);
            } catch (const Error&) {
                continue;  // at or below the curve's floor: no density
            }
        }
        if (std::isnan(t_block0)) t_block0 = a.time_s;
        obs.push_back({rho, a.beams[g], a.errors[g], int(std::floor((a.time_s - t_block0) / block_s))});
    }
    return obs;
}

/// The densest regional smoke state of the scene on these beams (its shape is scaled to each
/// density), its mean density and time; best = 0 when there is no regional smoke on them.
struct DensestState {
    SmokeField field;
    double mean_density = 0, time_s = NAN;
};

DensestState densestState(const Scene& scene, const GroupBeams& gb, double step_s)
{
    DensestState d;
    for (double t = scene.t_start_s; t <= scene.t_end_s + 1e-9; t += step_s) {
        SmokeField f = SmokeField::at(scene.volumes, t);
        double rho_mean = 0;
        for (size_t b = 0; b < gb.rays.size(); ++b)
            rho_mean += f.trace(gb.rays[b], 0.0, gb.L[b], BeamQuery{}).column_regional / gb.L[b];
        rho_mean /= double(gb.rays.size());
        if (rho_mean > d.mean_density) {
            d.mean_density = rho_mean;
            d.field = std::move(f);
            d.time_s = t;
        }
    }
    return d;
}

/// The AMCW amplitudes of each beam on a density grid up to rho_max, the smoke state scaled.
AmplitudeTable amplitudeTable(const Scene& scene, const SurfaceSet& surfaces, const SensorMount& mount,
                              const LrfSpec& spec, const GroupBeams& gb, const DensestState& d, double rho_max,
                              int grid)
{
    AmplitudeTable tab;
    tab.n = std::max(3, grid);
    tab.rho_max = rho_max;
    tab.beam.assign(gb.rays.size(), std::vector<AmcwAmplitudes>(size_t(tab.n)));
    const PhysicalParams& p = mount.config.physical;
    for (int j = 0; j < tab.n; ++j) {
        const SmokeField scaled = d.field.scaledRegional(tab.rho_max * j / (tab.n - 1) / d.mean_density);
        for (size_t b = 0; b < gb.rays.size(); ++b)
            tab.beam[b][size_t(j)] =
                amcwAmplitudes(p, traceBeamSignal(gb.rays[b], spec, p, scene, surfaces, scaled, nullptr, nullptr));
    }
    return tab;
}

/// The calibration curve's share of θ's error: every density moved by its relative standard
/// error at S*, θ refitted.
double calibrationError(const AmplitudeTable& tab, const PhysicalParams& p, const std::vector<Obs>& obs,
                        const ThetaFit& f, const ThresholdFit& th, const CurveFitResult& calib, int iterations)
{
    try {
        const auto [rho_s, se_rho] = calib.invert(th.S_star.value, 0.0);
        if (rho_s > 0 && se_rho > 0) {
            std::vector<Obs> moved = obs;
            for (Obs& o : moved) o.rho *= 1 + se_rho / rho_s;
            const ThetaFit f2 = fitTheta(tab, p, moved, iterations);  // the table holds beyond its end
            if (f2.ok) return std::abs(f2.theta - f.theta);
        }
    } catch (const Error&) {
    }
    return 0;
}

/// Where the fitted model errs half the time, as a column over the group's mean distance, and
/// its spread over θ ± se.
Estimate onsetColumn(const AmplitudeTable& tab, const PhysicalParams& p, const std::vector<double>& L, double theta,
                     double se_theta)
{
    double Lm = 0;
    for (double l : L) Lm += l / double(L.size());
    auto rhoAtHalf = [&](double th) {
        double lo = 0, hi = tab.rho_max;
        if (groupErrorProbability(tab, p, th, hi) < 0.5) return double(NAN);
        for (int it = 0; it < 60; ++it) {
            const double mid = 0.5 * (lo + hi);
            (groupErrorProbability(tab, p, th, mid) < 0.5 ? lo : hi) = mid;
        }
        return 0.5 * (lo + hi);
    };
    const double c0 = rhoAtHalf(theta) * Lm;
    const double ca = rhoAtHalf(theta - se_theta) * Lm, cb = rhoAtHalf(theta + se_theta) * Lm;
    return {c0, 0.5 * std::abs(ca - cb)};
}

}  // namespace

UrgNoiseFloorResult fitUrgNoiseFloor(const Scene& scene, const SurfaceSet& surfaces, const SensorMount& mount,
                                     const SensorFitResult& fit, size_t g, const CurveFitResult& calib,
                                     const UrgNoiseFloorConfig& cfg)
{
    const LrfSpec spec = specFor(mount.config);
    if (!laserKind(spec.type).fitsPhysicalModel())
        throw Error(
            "--model physical",
            std::string("the noise floor fit is for the URG-04LX (AMCW); not for the ") + sensorTypeName(spec.type));
    UrgNoiseFloorResult out;
    const BeamGroup& group = fit.groups.at(g);
    const ThresholdFit& th = fit.thresholds.at(g);
    out.group = group.name;
    auto fail = [&](const std::string& why) {
        out.diagnosis = why;
        return out;
    };
    if (!th.fitted) return fail("group '" + group.name + "' has no fitted threshold");
    const GroupBeams gb = groupBeams(surfaces, mount, spec, group);
    out.beams = int(gb.rays.size());
    if (gb.rays.empty()) return fail("group '" + group.name + "' has no beam of this sensor in the scene");
    const std::vector<Obs> obs = densityObservations(fit, g, calib, cfg.block_s);
    double rho_obs_max = 0;
    for (const Obs& o : obs) rho_obs_max = std::max(rho_obs_max, o.rho);
    out.scans = int(obs.size());
    if (obs.size() < 3 || !(rho_obs_max > 0)) return fail("too few aligned scans with smoke for '" + group.name + "'");
    const DensestState d = densestState(scene, gb, cfg.time_step_s);
    out.scene_time_s = d.time_s;
    if (!(d.mean_density > 0)) return fail("the scene has no regional smoke on the beams of '" + group.name + "'");
    const PhysicalParams& p = mount.config.physical;
    const AmplitudeTable tab = amplitudeTable(scene, surfaces, mount, spec, gb, d, 1.05 * rho_obs_max, cfg.grid);
    const ThetaFit f = fitTheta(tab, p, obs, cfg.iterations);
    if (!f.ok) return fail("the noise floor fit did not converge");
    const double se_cal = calibrationError(tab, p, obs, f, th, calib, cfg.iterations);
    const double nf = std::exp(f.theta);
    const double var_stat = std::max(f.var_model, f.var_robust);
    out.variance_inflation = f.var_robust / f.var_model;
    out.se_statistical = nf * std::sqrt(var_stat);
    out.se_calibration = nf * se_cal;
    out.noise_floor = {nf, nf * std::sqrt(var_stat + se_cal * se_cal)};
    out.pearson_chi2 = f.chi2;
    out.dof = int(obs.size()) - 1;
    out.onset_column = onsetColumn(tab, p, gb.L, f.theta, std::sqrt(var_stat + se_cal * se_cal));
    out.ok = true;
    return out;
}

}  // namespace smokescan
