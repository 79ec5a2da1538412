#pragma once
// The solve module (internal, header-only): the Ceres side every fit shares (calib, fit and
// diagnose link it; only their .cpp files include it): a quiet solver, the solve and its
// convergence, a parameter block's covariance, and the cluster-robust ("sandwich") covariance.
//
// Ceres logs through glog (rank-deficient covariances, line-search notes). The library leaves
// glog's flags to the program: the CLI silences it (src/cli/main.cpp), since the fits report
// what matters in their results and diagnoses.
#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <map>
#include <vector>

namespace smokescan::detail {

/// @brief Quiet dense-QR solver options for the calibration's small problems.
inline ceres::Solver::Options denseOptions(int max_iterations, double tolerance)
{
    ceres::Solver::Options opt;
    opt.linear_solver_type = ceres::DENSE_QR;
    opt.max_num_iterations = max_iterations;
    opt.function_tolerance = tolerance;
    opt.parameter_tolerance = tolerance;
    opt.logging_type = ceres::SILENT;
    return opt;
}

/// @brief Solves quietly with the given options; true when the solution is usable and converged.
inline bool solveQuiet(ceres::Problem& problem, const ceres::Solver::Options& options, ceres::Solver::Summary& summary)
{
    ceres::Solve(options, &problem, &summary);
    return summary.IsSolutionUsable() && summary.termination_type == ceres::CONVERGENCE;
}

/// @brief True when a solve that used up its iterations had stopped moving: the cost fell by
/// less than 1e-3 of itself over the last 100 iterations (a parameter creeping along a flat
/// direction, e.g. towards a bound, while the fit is at its minimum: χ² then moves by less than
/// 0.01 per 10 degrees of freedom).
inline bool stalledAtMinimum(const ceres::Solver::Summary& s)
{
    const size_t n = s.iterations.size();
    return s.IsSolutionUsable() && s.termination_type == ceres::NO_CONVERGENCE && n > 100 &&
        s.iterations[n - 100].cost - s.final_cost < 1e-3 * s.final_cost;
}

/// @brief The n×n covariance (row-major into C) of one parameter block, from the problem's
/// Jacobian at the current values; false when Ceres cannot compute it (rank deficient).
inline bool blockCovariance(ceres::Problem& problem, const double* block, double* C)
{
    ceres::Covariance cov(ceres::Covariance::Options{});
    const std::vector<const double*> b{block};
    return cov.Compute(b, &problem) && cov.GetCovarianceMatrix(b, C);
}

/// Which clusters the small-sample correction m/(m − 1) counts: every cluster holding a residual
/// (the threshold fit), or only those whose score is not zero (the noise-floor fit, whose blocks
/// without smoke carry no information about it). The two fits have always differed here; which
/// convention the pull tests support is open (docs/fitting.md).
enum class ClusterCount { WithData, Informative };

/// Model-based and cluster-robust covariance of a problem's free parameters.
struct ClusterCovariance {
    Eigen::MatrixXd model;  ///< (JᵀJ)⁻¹ (pseudo-inverse): the Fisher information's inverse
    Eigen::MatrixXd robust;  ///< m/(m − 1)·A⁻¹·B·A⁻¹, B = Σ over clusters of their score outer products
    int clusters = 0;  ///< m, as counted by ClusterCount
};

/// @brief The covariance at the solution from a problem of Pearson residuals (their JᵀJ is the
/// Fisher information), robust to correlation within clusters: residual i belongs to cluster
/// cluster_of[i]. Model-based A⁻¹ alone would count correlated residuals (the beams of one scan,
/// scans within one camera frame, scans of one time block) as independent and understate the
/// errors. Columns are ordered as `blocks` (each block's parameters in turn).
inline ClusterCovariance clusterRobustCovariance(ceres::Problem& problem, const std::vector<double*>& blocks,
                                                 const std::vector<long long>& cluster_of, ClusterCount count)
{
    ceres::Problem::EvaluateOptions eo;
    eo.parameter_blocks = blocks;
    std::vector<double> r;
    ceres::CRSMatrix jac;
    problem.Evaluate(eo, nullptr, &r, nullptr, &jac);
    const int P = jac.num_cols;
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(jac.num_rows, P);
    for (int row = 0; row < jac.num_rows; ++row)
        for (int i = jac.rows[size_t(row)]; i < jac.rows[size_t(row) + 1]; ++i)
            J(row, jac.cols[size_t(i)]) = jac.values[size_t(i)];
    std::map<long long, Eigen::VectorXd> score;
    for (size_t row = 0; row < r.size() && row < cluster_of.size(); ++row) {
        auto it = score.try_emplace(cluster_of[row], Eigen::VectorXd::Zero(P)).first;
        it->second += J.row(long(row)).transpose() * r[row];
    }
    Eigen::MatrixXd B = Eigen::MatrixXd::Zero(P, P);
    ClusterCovariance out;
    for (const auto& [c, v] : score) {
        B += v * v.transpose();
        out.clusters += count == ClusterCount::WithData || !v.isZero(0.0);
    }
    out.model = (J.transpose() * J).completeOrthogonalDecomposition().pseudoInverse();
    // Small-sample correction of the cluster-robust estimator: m/(m − 1) for m clusters.
    const double m = double(out.clusters), corr = m > 1 ? m / (m - 1) : 1.0;
    const Eigen::MatrixXd C = out.model * B * out.model;
    out.robust = corr * C;
    return out;
}

}  // namespace smokescan::detail
