// Maximum likelihood for the binomial threshold model with Ceres: Levenberg–Marquardt on signed
// deviance residuals sign(e − n·p)·√d, whose squares sum to the deviance, so the minimum is the
// likelihood's maximum. (Fisher scoring — Gauss–Newton on Pearson residuals with frozen weights —
// could fall into a two-cycle on a run with a sparse error tail; a direct objective cannot.) The
// covariance uses Pearson residuals with the weights at the solution: their JᵀJ is the Fisher
// information, their score sums the cluster-robust middle.
#include "threshold_fit.hpp"
#include "ceres_fit.hpp"
#include "smokescan/core/order_stats.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <map>

#include <Eigen/Dense>

namespace smokescan::detail {
namespace {

/// The scan's signed deviance residual (binomial_deviance.hpp).
struct DevianceResidual {
    const SaturationSeries* sat;
    double t, n, e, sigma_S;
    bool logistic;
    template <class T>
    bool operator()(const T* offset, const T* sw, T* r) const
    {
        const T S = interpolate(*sat, T(t) + offset[0]);
        const T w = sqrt(sw[1] * sw[1] + T(sigma_S * sigma_S));
        T p, q;
        tails((sw[0] - S) / w, logistic, p, q);
        r[0] = signedDeviance(n, e, p, q);
        return true;
    }
};

struct PearsonResidual {
    const SaturationSeries* sat;
    double t, n, e, weight, sigma_S;
    bool logistic;
    template <class T>
    bool operator()(const T* offset, const T* sw, T* r) const
    {
        const T S = interpolate(*sat, T(t) + offset[0]);
        const T w = sqrt(sw[1] * sw[1] + T(sigma_S * sigma_S));
        T p, q;
        tails((sw[0] - S) / w, logistic, p, q);
        r[0] = (T(e) - T(n) * p) * T(weight);
        return true;
    }
};

double clampP(double p) { return std::clamp(p, 1e-9, 1 - 1e-9); }

}  // namespace

double errorProbability(double S, double S_star, double w, bool logistic)
{
    double p, q;
    tails((S_star - S) / w, logistic, p, q);
    return p;
}

double noiseOfSeries(const std::vector<double>& y)
{
    if (y.size() < 5) return 0;
    std::vector<double> d;
    for (size_t i = 1; i + 1 < y.size(); ++i) d.push_back(std::abs(y[i - 1] - 2 * y[i] + y[i + 1]));
    return median(std::move(d)) / 0.6745 / std::sqrt(6.0);
}

namespace {

/// The model's error probability for group g's scan k at offset `off` and (S*, w) = x.
double modelProbability(const ThresholdProblem& p, size_t g, size_t k, double off, const std::array<double, 2>& x)
{
    return errorProbability(interpolate(*p.sat, p.groups[g].t[k] + off), x[0], std::hypot(x[1], p.sigma_S), p.logistic);
}

/// Per group: Pearson χ², deviance, covariance of (S*, w) and its inflation over the model's.
void groupStatistics(const ThresholdProblem& p, double offset, const std::vector<std::array<double, 2>>& sw,
                     const ClusterCovariance& cc, ThresholdSolution& sol)
{
    const size_t G = p.groups.size();
    const int o = p.fit_offset ? 1 : 0;
    sol.cov.assign(G, Eigen::Matrix2d::Constant(NAN));
    sol.pearson_chi2.assign(G, 0);
    sol.deviance.assign(G, 0);
    sol.inflation.assign(G, NAN);
    sol.nobs.assign(G, 0);
    for (size_t g = 0; g < G; ++g) {
        const auto& d = p.groups[g];
        for (size_t k = 0; k < d.t.size(); ++k) {
            const double n = d.n[k], e = d.e[k], q = clampP(modelProbability(p, g, k, offset, sw[g]));
            sol.pearson_chi2[g] += (e - n * q) * (e - n * q) / (n * q * (1 - q));
            const double a = e > 0 ? e * std::log(e / (n * q)) : 0,
                         b = e < n ? (n - e) * std::log((n - e) / (n * (1 - q))) : 0;
            sol.deviance[g] += 2 * (a + b);
        }
        sol.nobs[g] = int(d.t.size());
        const int i = o + 2 * int(g);
        sol.cov[g] = cc.robust.block(i, i, 2, 2);
        sol.inflation[g] = cc.model(i, i) > 0 ? sol.cov[g](0, 0) / cc.model(i, i) : NAN;
    }
}

}  // namespace

ThresholdSolution solveThresholds(const ThresholdProblem& p)
{
    const size_t G = p.groups.size();
    ThresholdSolution sol;
    double offset = p.offset0;
    std::vector<std::array<double, 2>> sw = p.start;
    // One problem over all groups and the shared offset; `pearson` builds the covariance's
    // residuals (weights at the current solution), else the deviance's.
    auto build = [&](ceres::Problem& problem, bool pearson) {
        problem.AddParameterBlock(&offset, 1);
        if (!p.fit_offset) problem.SetParameterBlockConstant(&offset);
        bool any = false;
        for (size_t g = 0; g < G; ++g) {
            problem.AddParameterBlock(sw[g].data(), 2);
            problem.SetParameterLowerBound(sw[g].data(), 1, p.sigma_S > 0 ? 0.0 : kMinWidth);
            for (size_t k = 0; k < p.groups[g].t.size(); ++k) {
                const double n = p.groups[g].n[k], e = p.groups[g].e[k];
                ceres::CostFunction* cost;
                if (pearson) {
                    const double p0 = clampP(modelProbability(p, g, k, offset, sw[g]));
                    cost = new ceres::AutoDiffCostFunction<PearsonResidual, 1, 1, 2>(new PearsonResidual{
                        p.sat, p.groups[g].t[k], n, e, 1.0 / std::sqrt(n * p0 * (1 - p0)), p.sigma_S, p.logistic});
                } else {
                    cost = new ceres::AutoDiffCostFunction<DevianceResidual, 1, 1, 2>(
                        new DevianceResidual{p.sat, p.groups[g].t[k], n, e, p.sigma_S, p.logistic});
                }
                problem.AddResidualBlock(cost, nullptr, &offset, sw[g].data());
                any = true;
            }
        }
        return any;
    };
    ceres::Problem ml;
    if (!build(ml, false)) return sol;
    ceres::Solver::Options opt;
    opt.max_num_iterations = 500;
    opt.linear_solver_type = ceres::DENSE_QR;
    // The deviance's Gauss-Newton steps converge linearly (about 0.3–0.4 a step): a relative
    // cost change of 1e-10 leaves S* within about 1e-6 of the optimum (its errors are ~1e-2);
    // 1e-14 spent a fifth of a fit's steps below that (and the bootstrap refits 30 times).
    opt.function_tolerance = 1e-10;
    opt.gradient_tolerance = 1e-14;
    opt.parameter_tolerance = 1e-12;
    ceres::Solver::Summary summary;
    sol.converged = solveQuiet(ml, opt, summary);
    sol.message = summary.BriefReport();
    // Covariance at the solution, cluster-robust over the scans of one cluster (the beams of one
    // scan share their smoke; scans within one camera frame share its noise).
    ceres::Problem problem;
    build(problem, true);
    std::vector<double*> blocks;
    if (p.fit_offset) blocks.push_back(&offset);
    for (size_t g = 0; g < G; ++g) blocks.push_back(sw[g].data());
    std::vector<long long> cluster_of;
    for (size_t g = 0; g < G; ++g)
        for (double t : p.groups[g].t) cluster_of.push_back((long long)std::floor(t / p.cluster_s));
    const ClusterCovariance cc = clusterRobustCovariance(problem, blocks, cluster_of, ClusterCount::WithData);
    sol.offset = offset;
    sol.sw = sw;
    groupStatistics(p, offset, sw, cc, sol);
    if (p.fit_offset) sol.offset_se = std::sqrt(std::max(0.0, cc.robust(0, 0)));
    return sol;
}

}  // namespace smokescan::detail
