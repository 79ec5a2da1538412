#include "smokescan/calib/light_mixing.hpp"

#include <cmath>

#include "ceres_fit.hpp"
#include "smokescan/core/error.hpp"

namespace smokescan {
namespace {

/// One patch's channel: x = l·T + A·(1 − T).
struct MixingResidual {
    double l, x;
    template <class T>
    bool operator()(const T* const tr, const T* const a, T* r) const
    {
        r[0] = T(x) - T(l) * tr[0] - a[0] * (T(1.0) - tr[0]);
        return true;
    }
};

}  // namespace

LightMixing measureLightMixing(double density, const std::vector<std::array<double, 3>>& clear,
                               const std::vector<std::array<double, 3>>& seen)
{
    if (clear.size() < 2 || clear.size() != seen.size())
        throw Error("calibration", "the light's mixing needs the same two or more patches in clear air and in smoke");
    LightMixing m;
    m.density = density;
    if (density <= 0) return m;
    double mean = 0;
    for (const auto& x : seen)
        for (double v : x) mean += v / double(3 * seen.size());
    double tr = 0.5;
    std::array<double, 3> a{{mean, mean, mean}};
    ceres::Problem problem;
    for (size_t p = 0; p < seen.size(); ++p)
        for (size_t c = 0; c < 3; ++c)
            problem.AddResidualBlock(
                new ceres::AutoDiffCostFunction<MixingResidual, 1, 1, 1>(new MixingResidual{clear[p][c], seen[p][c]}),
                nullptr, &tr, &a[c]);
    problem.SetParameterLowerBound(&tr, 0, 1e-9);
    problem.SetParameterUpperBound(&tr, 0, 1 - 1e-9);
    const ceres::Solver::Options opt = detail::denseOptions(500, 1e-14);
    ceres::Solver::Summary summary;
    detail::solveQuiet(problem, opt, summary);
    m.transmittance = tr;
    m.scattered = a;
    const int n = int(3 * seen.size()), dof = n - 4;
    m.rms = mean > 0 ? std::sqrt(2 * summary.final_cost / n) / mean : 0.0;
    // T's error: the unweighted fit's covariance scaled by the residual variance.
    double var = 0;
    if (dof > 0 && detail::blockCovariance(problem, &tr, &var))
        m.transmittance_se = std::sqrt(std::max(0.0, var * 2 * summary.final_cost / dof));
    return m;
}

std::pair<double, double> extinctionPath(const std::vector<LightMixing>& m)
{
    double sxy = 0, sxx = 0;  // −ln T = b·ρ, weighted by 1/σ²(−ln T) = (T/σ_T)²
    for (const auto& q : m)
        if (q.density > 0 && q.transmittance >= 0.02 && q.transmittance <= 0.98 && q.transmittance_se > 0) {
            const double w = std::pow(q.transmittance / q.transmittance_se, 2);
            sxy += w * q.density * -std::log(q.transmittance);
            sxx += w * q.density * q.density;
        }
    return sxx > 0 ? std::pair{sxy / sxx, 1 / std::sqrt(sxx)} : std::pair{0.0, 0.0};
}

}  // namespace smokescan
