#pragma once
// The binomial threshold fit behind fitSensor (internal): per group of beams, errors e of n per
// scan against the saturation at scan time + δ, by maximum likelihood (signed deviance residuals)
// with Ceres.
#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "binomial_deviance.hpp"
#include "smokescan/io/recorded.hpp"

namespace smokescan::detail {

/// One group's observations: per scan, the laser time and errors e out of n beams.
struct GroupCounts {
    std::vector<double> t;
    std::vector<int> n, e;
};

struct ThresholdProblem {
    const SaturationSeries* sat = nullptr;
    std::vector<GroupCounts> groups;
    bool logistic = false;
    bool fit_offset = true;
    double offset0 = 0;
    std::vector<std::array<double, 2>> start;  ///< (S*, w) per group
    /// Residuals of scans within one block of this length [s] form one cluster of the robust
    /// covariance: beams of a scan share their smoke, and scans within a camera frame its noise.
    double cluster_s = 1.0;
    /// Measurement noise of the saturation: the observed width is √(w² + sigma_S²), since a step
    /// in the true saturation is blurred by the noise of the measured one (errors in variables).
    double sigma_S = 0;
};

struct ThresholdSolution {
    double offset = 0, offset_se = NAN;
    std::vector<std::array<double, 2>> sw;  ///< (S*, w)
    std::vector<Eigen::Matrix2d> cov;  ///< of (S*, w), cluster-robust
    std::vector<double> pearson_chi2, deviance;
    std::vector<double> inflation;  ///< robust / model-based variance of S*
    std::vector<int> nobs;  ///< scans used per group
    bool converged = false;
    std::string message;
};

/// Saturation at time t, linear between samples, held at the ends; T a double or a Ceres Jet
/// (the fit differentiates it in the clock offset).
template <class T>
T interpolate(const SaturationSeries& s, const T& t)
{
    const auto& ts = s.time_s;
    const double td = scalar(t);
    if (ts.size() == 1 || td <= ts.front()) return T(s.saturation.front());
    if (td >= ts.back()) return T(s.saturation.back());
    const size_t i = size_t(std::upper_bound(ts.begin(), ts.end(), td) - ts.begin()) - 1;
    const double dt = ts[i + 1] - ts[i];
    if (!(dt > 0)) return T(s.saturation[i]);
    return T(s.saturation[i]) + T(s.saturation[i + 1] - s.saturation[i]) * (t - T(ts[i])) / T(dt);
}

/// Smallest width the fit may reach; at it the step is called sharp.
constexpr double kMinWidth = 1e-4;

/// Robust noise level of a series sampled densely enough that it is locally linear: the MAD of
/// its second differences, which have variance 6σ² for white noise.
double noiseOfSeries(const std::vector<double>& y);

/// P(error) at saturation S for threshold S* and width w.
double errorProbability(double S, double S_star, double w, bool logistic);

ThresholdSolution solveThresholds(const ThresholdProblem& p);

}  // namespace smokescan::detail
