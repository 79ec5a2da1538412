// The saturation curve and its Ceres fit.
#include "smokescan/calib/saturation_curve.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <set>

#include "ceres_fit.hpp"
#include "smokescan/core/error.hpp"

namespace smokescan {
namespace {

template <class T>
T curveValue(const T& rho, const T& S0, const T& a, const T& b, double gamma)
{
    using std::exp;
    using std::pow;
    const T s_lin = S0 / (T(1.0) + a * (exp(b * rho) - T(1.0)));
    return T(1.0) - pow(T(1.0) - s_lin, T(gamma));
}

/// Residual of one point, in units of its standard error.
struct SaturationResidual {
    SaturationResidual(double rho, double S, double sigma, double gamma, double floor)
        : rho_(rho), S_(S), sigma_(sigma), gamma_(gamma), floor_(floor)
    {
    }
    template <class T>
    bool operator()(const T* const p, T* r) const
    {
        using std::sqrt;
        const T c = curveValue(T(rho_), p[0], p[1], p[2], gamma_);
        r[0] = (sqrt(c * c + T(floor_ * floor_)) - T(S_)) / T(sigma_);
        return true;
    }
    double rho_, S_, sigma_, gamma_, floor_;
};

/// ρ(S) for the delta method, templated so Ceres' Jets give its gradient.
template <class T>
T inverseValue(double S, const T& S0, const T& a, const T& b, double gamma)
{
    using std::log;
    using std::pow;
    const T s_lin = T(1.0) - pow(T(1.0 - S), T(1.0 / gamma));
    return log(T(1.0) + (S0 / s_lin - T(1.0)) / a) / b;
}

}  // namespace

double SaturationCurve::operator()(double rho) const { return std::hypot(curveValue(rho, S0, a, b, gamma), floor); }

double SaturationCurve::invert(double S) const
{
    if (!std::isfinite(S) || S <= floor)
        throw Error("",
                    "saturation " + std::to_string(S) +
                        " is never reached (the curve only tends to the camera's noise floor " + std::to_string(floor) +
                        ")");
    if (S >= (*this)(0.0))
        throw Error(
            "",
            "saturation " + std::to_string(S) + " is at or above the clear-air value " + std::to_string((*this)(0.0)));
    return inverseValue(std::sqrt(S * S - floor * floor), S0, a, b, gamma);
}

std::pair<double, double> CurveFitResult::invert(double S, double sigma_S) const
{
    const double rho = curve.invert(S);
    using J = ceres::Jet<double, 4>;
    const J s0(curve.S0, 0), a(curve.a, 1), b(curve.b, 2);
    // d/dS by a central difference (S enters through pow of a constant).
    const double h = 1e-6;
    const double dS = sigma_S > 0 ? (curve.invert(std::max(1e-9, S - h)) - curve.invert(S + h)) / (-2 * h) : 0.0;
    const J r = inverseValue(std::sqrt(S * S - curve.floor * curve.floor), s0, a, b, curve.gamma);
    const Eigen::Vector3d g(r.v[0], r.v[1], r.v[2]);
    const double var = g.dot(covariance * g) + dS * dS * sigma_S * sigma_S;
    return {rho, std::sqrt(std::max(0.0, var))};
}

CurveFitResult fitSaturationCurve(const std::vector<SaturationPoint>& pts, const CurveFitConfig& cfg)
{
    std::set<double> distinct;
    double smin = 1e300, smax = -1e300;
    for (size_t i = 0; i < pts.size(); ++i) {
        const auto& p = pts[i];
        const std::string where = "calibration point " + std::to_string(i + 1);
        if (!std::isfinite(p.density) || !std::isfinite(p.saturation) || !std::isfinite(p.sigma))
            throw Error(where,
                        "is not finite (density " + std::to_string(p.density) + ", saturation " +
                            std::to_string(p.saturation) + ")");
        if (p.density < 0) throw Error(where, "has a negative density");
        if (p.saturation < 0 || p.saturation > 1) throw Error(where, "has a saturation outside [0, 1]");
        if (!(p.sigma > 0)) throw Error(where, "has a standard error <= 0");
        distinct.insert(p.density);
        smin = std::min(smin, p.saturation);
        smax = std::max(smax, p.saturation);
    }
    if (distinct.size() < 4)
        throw Error("calibration",
                    "needs at least 4 distinct densities to fit 3 parameters, got " + std::to_string(distinct.size()));
    if (!(smax - smin > 1e-6)) throw Error("calibration", "saturation does not change with density: nothing to fit");

    // Start: S0 from the clearest point, b from where the saturation halves, a = 1.
    std::vector<SaturationPoint> sorted = pts;
    std::sort(sorted.begin(), sorted.end(), [](auto& x, auto& y) { return x.density < y.density; });
    double p[3] = {std::min(0.99, std::max(0.05, 1 - std::pow(1 - sorted.front().saturation, 1 / cfg.gamma))), 1.0,
                   0.0};
    double rho_half = sorted.back().density;
    for (const auto& q : sorted)
        if (q.saturation < 0.5 * sorted.front().saturation) {
            rho_half = q.density;
            break;
        }
    p[2] = std::log(2.0) / std::max(rho_half, 1e-12);

    ceres::Problem problem;
    for (const auto& q : pts) {
        ceres::LossFunction* loss = nullptr;
        switch (cfg.loss) {
        case RobustLoss::None:
            break;
        case RobustLoss::Huber:
            loss = new ceres::HuberLoss(cfg.loss_scale);
            break;
        case RobustLoss::Cauchy:
            loss = new ceres::CauchyLoss(cfg.loss_scale);
            break;
        }
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<SaturationResidual, 1, 3>(
                                     new SaturationResidual(q.density, q.saturation, q.sigma, cfg.gamma, cfg.floor)),
                                 loss, p);
    }
    problem.SetParameterLowerBound(p, 0, 1e-6);
    problem.SetParameterUpperBound(p, 0, 1.0);
    problem.SetParameterLowerBound(p, 1, 1e-9);
    problem.SetParameterLowerBound(p, 2, 1e-9);
    const ceres::Solver::Options opt = detail::denseOptions(1000, 1e-12);
    ceres::Solver::Summary summary;
    ceres::Solve(opt, &problem, &summary);

    CurveFitResult res;
    res.curve = SaturationCurve{p[0], p[1], p[2], cfg.gamma, cfg.floor};
    res.converged = summary.termination_type == ceres::CONVERGENCE && summary.IsSolutionUsable();
    res.message = summary.BriefReport();
    double mean = 0;
    for (const auto& q : pts) mean += q.saturation;
    mean /= pts.size();
    double ss_res = 0, ss_tot = 0;
    for (const auto& q : pts) {
        const double r = res.curve(q.density) - q.saturation;
        res.chi2 += (r / q.sigma) * (r / q.sigma);
        ss_res += r * r;
        ss_tot += (q.saturation - mean) * (q.saturation - mean);
    }
    res.dof = int(pts.size()) - 3;
    res.r2 = ss_tot > 0 ? 1 - ss_res / ss_tot : 0;

    // The covariance's SVD is only defined on a finite Jacobian: densities far beyond the curve's
    // range underflow it (and Eigen's SVD then never returns).
    ceres::CRSMatrix jac;
    double cost = 0;
    const bool finite_jacobian = problem.Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr, nullptr, &jac) &&
        std::all_of(jac.values.begin(), jac.values.end(), [](double v) { return std::isfinite(v); });
    ceres::Covariance::Options copt;
    copt.algorithm_type = ceres::DENSE_SVD;
    copt.null_space_rank = -1;
    ceres::Covariance cov(copt);
    std::vector<std::pair<const double*, const double*>> blocks = {{p, p}};
    if (finite_jacobian && cov.Compute(blocks, &problem)) {
        double c[9];
        cov.GetCovarianceBlock(p, p, c);
        res.covariance = Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(c);
        if (cfg.scale_covariance_by_chi2 && res.dof > 0) res.covariance *= std::max(1.0, res.chi2 / res.dof);
    } else {
        res.converged = false;
        res.message += " (covariance could not be computed: the curve is not identifiable from these points)";
    }
    for (int k = 0; k < 3; ++k) res.std_error[size_t(k)] = std::sqrt(std::max(0.0, res.covariance(k, k)));
    if (res.converged && !(res.std_error[0] > 0 && res.std_error[1] > 0 && res.std_error[2] > 0)) {
        res.converged = false;
        res.message += " (a parameter has no standard error: the curve is not identifiable from these points)";
    }
    return res;
}

}  // namespace smokescan
