// Maximum likelihood for the binomial threshold model with Ceres: Levenberg–Marquardt on signed
// deviance residuals sign(e − n·p)·√d, whose squares sum to the deviance, so the minimum is the
// likelihood's maximum. (Fisher scoring — Gauss–Newton on Pearson residuals with frozen weights —
// could fall into a two-cycle on a run with a sparse error tail; a direct objective cannot.) The
// covariance uses Pearson residuals with the weights at the solution: their JᵀJ is the Fisher
// information, their score sums the cluster-robust middle.
#include "threshold_fit.hpp"
#include "../calib/ceres_quiet.hpp"
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

ThresholdSolution solveThresholds(const ThresholdProblem& p)
{
    const size_t G = p.groups.size();
    ThresholdSolution sol;
    double offset = p.offset0;
    std::vector<std::array<double, 2>> sw = p.start;
    auto pAt = [&](size_t g, size_t k, double off, const std::array<double, 2>& x) {
        return errorProbability(interpolate(*p.sat, p.groups[g].t[k] + off), x[0], std::hypot(x[1], p.sigma_S), p.logistic);
    };
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
                    const double p0 = clampP(pAt(g, k, offset, sw[g]));
                    cost = new ceres::AutoDiffCostFunction<PearsonResidual, 1, 1, 2>(
                        new PearsonResidual{p.sat, p.groups[g].t[k], n, e, 1.0 / std::sqrt(n * p0 * (1 - p0)), p.sigma_S, p.logistic});
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
    detail::quietCeres();
    ceres::Solver::Options opt;
    opt.max_num_iterations = 500;
    opt.linear_solver_type = ceres::DENSE_QR;
    opt.function_tolerance = 1e-14;
    opt.gradient_tolerance = 1e-14;
    opt.parameter_tolerance = 1e-12;
    ceres::Solver::Summary summary;
    ceres::Solve(opt, &ml, &summary);
    const bool converged = summary.IsSolutionUsable() && summary.termination_type == ceres::CONVERGENCE;
    {
        ceres::Problem problem;
        build(problem, true);
        // Covariance at the solution, cluster-robust: A⁻¹·B·A⁻¹ with A = JᵀJ (the Fisher
        // information: the weights are those of the solution) and B the sum over clusters of
        // their score outer products. Model-based A⁻¹ alone would treat the beams of one scan, which
        // share their smoke, and scans within one camera frame, which share its noise, as
        // independent and understate the errors many times over.
        std::vector<double*> blocks;
        if (p.fit_offset) blocks.push_back(&offset);
        for (size_t g = 0; g < G; ++g) blocks.push_back(sw[g].data());
        ceres::Problem::EvaluateOptions eo;
        eo.parameter_blocks = blocks;
        std::vector<double> r;
        ceres::CRSMatrix jac;
        problem.Evaluate(eo, nullptr, &r, nullptr, &jac);
        const int P = jac.num_cols;
        Eigen::MatrixXd J = Eigen::MatrixXd::Zero(jac.num_rows, P);
        for (int row = 0; row < jac.num_rows; ++row)
            for (int i = jac.rows[size_t(row)]; i < jac.rows[size_t(row) + 1]; ++i) J(row, jac.cols[size_t(i)]) = jac.values[size_t(i)];
        const Eigen::MatrixXd A = J.transpose() * J;
        std::map<long long, Eigen::VectorXd> score;
        size_t row = 0;
        for (size_t g = 0; g < G; ++g)
            for (size_t k = 0; k < p.groups[g].t.size(); ++k, ++row) {
                const long long c = (long long)std::floor(p.groups[g].t[k] / p.cluster_s);
                auto it = score.try_emplace(c, Eigen::VectorXd::Zero(P)).first;
                it->second += J.row(long(row)).transpose() * r[row];
            }
        Eigen::MatrixXd B = Eigen::MatrixXd::Zero(P, P);
        for (const auto& [c, v] : score) B += v * v.transpose();
        const Eigen::MatrixXd Ainv = A.completeOrthogonalDecomposition().pseudoInverse();
        const Eigen::MatrixXd C = Ainv * B * Ainv;
        // Small-sample correction of the cluster-robust estimator: m/(m − 1) for m clusters.
        const double m = double(score.size()), corr = m > 1 ? m / (m - 1) : 1.0;
        const int o = p.fit_offset ? 1 : 0;
        sol.offset = offset;
        sol.sw = sw;
        sol.cov.assign(G, Eigen::Matrix2d::Constant(NAN));
        sol.pearson_chi2.assign(G, 0);
        sol.deviance.assign(G, 0);
        sol.inflation.assign(G, NAN);
        sol.nobs.assign(G, 0);
        for (size_t g = 0; g < G; ++g) {
            const auto& d = p.groups[g];
            for (size_t k = 0; k < d.t.size(); ++k) {
                const double n = d.n[k], e = d.e[k], q = clampP(pAt(g, k, offset, sw[g]));
                sol.pearson_chi2[g] += (e - n * q) * (e - n * q) / (n * q * (1 - q));
                const double a = e > 0 ? e * std::log(e / (n * q)) : 0, b = e < n ? (n - e) * std::log((n - e) / (n * (1 - q))) : 0;
                sol.deviance[g] += 2 * (a + b);
            }
            sol.nobs[g] = int(d.t.size());
            const int i = o + 2 * int(g);
            sol.cov[g] = corr * C.block(i, i, 2, 2);
            sol.inflation[g] = Ainv(i, i) > 0 ? sol.cov[g](0, 0) / Ainv(i, i) : NAN;
        }
        if (p.fit_offset) sol.offset_se = std::sqrt(std::max(0.0, corr * C(0, 0)));
        sol.converged = converged;
        sol.message = summary.BriefReport();
    }
    return sol;
}

}  // namespace smokescan::detail
