#pragma once
/// @file predictive.hpp
/// @brief The predictive distribution of one logged beam: the probability that it reports an
/// error value, and the density of the range it reports when it does not, under the paper model
/// and the candidate extensions (docs/diagnosis.md). The log-likelihood of the recorded value is
/// the currency of the diagnosis.
///
/// Generative story of a beam at smoke column C [density·m] along it, to a surface at L [m]:
///  1. with probability d (sector dropout) it fails whatever the smoke;
///  2. else the smoke stops it with probability p_s = Φ((ln C − ln P)/w) (the paper's
///     penetration power P, a step when w → 0); a stopped beam returns a short range, uniform
///     on (0, L), with probability q (smoke obstacle return), else an error value;
///  3. else it reads N(L·(1 + β·C), σ₀(L)² + (γ·C)²), σ₀ the datasheet noise;
///
/// With the physical model (the URG-04LX's), p_s is the model's own error probability at the
/// smoke scaled by e^(−shift) (the threshold's shift ln(P'/P)), averaged over the width's
/// e^(w·z), and L is its noise-free range (diagnose/replay.hpp tabulates both per beam);
///  4. robustness: with probability ε = 1e-3 a beam lapses — it errs or reads a uniform range,
///     even odds — and a surface reading is an outlier, uniform over the sensor's range, with
///     probability η = 1e-3: no recorded value has probability zero, and no single beam costs
///     more than about 9 nats. These two are fixed, not fitted.
///
/// The parameters are a sensor file's extensions (ModelExtensions, sensor_config/extensions.hpp),
/// whose formulas (namespace extended) the simulation shares:
///
/// | parameter        | null (today's model) | unit          | extension                          |
/// |------------------|----------------------|---------------|------------------------------------|
/// | clock_offset_s   | 0                    | s             | clock_offset                        |
/// | ln P factor      | 0 per surface        | –             | surface_threshold                   |
/// | width w          | 0.02                 | ln(column)    | threshold_width                     |
/// | β                | 0 per surface        | 1/(density·m) | surface_range_bias                  |
/// | γ                | 0                    | m/(density·m) | range_noise_growth                  |
/// | q                | 0                    | –             | smoke_obstacle_return               |
/// | d                | 0 per sector         | –             | sector_dropout                      |
/// | h                | 0                    | –             | hysteresis: ln P(falling) − ln P(rising) |
#include <cmath>

#include "smokescan/sensor_config/extensions.hpp"

namespace smokescan {

constexpr double kLapse = 1e-3;  ///< ε
constexpr double kOutlier = 1e-3;  ///< η

/// One beam's terms of the predictive distribution; T a double or a Ceres Jet.
template <class T>
struct BeamTerms {
    T column;  ///< C [density·m]
    T lnP;  ///< ln of the penetration power that applies (surface, rising or falling)
    T width;  ///< w
    T beta;  ///< β
    T gamma;  ///< γ
    T q;  ///< obstacle return share
    T d;  ///< dropout
    T ps;  ///< P(the smoke stops the beam): Φ((ln C − ln P)/w) for the paper model (set by the caller)
    T mu0;  ///< the model's noise-free range [m]: L for the paper model
    T sd0;  ///< its noise [m] in clear air: σ₀(L), the datasheet's, for the paper model
};

/// @brief The normal density [1/m] of a surface reading `recorded_m` about the mean `mu` [m]
/// with variance `var` [m²].
template <class T>
T readingDensity(double recorded_m, const T& mu, const T& var)
{
    using std::exp;
    using std::sqrt;
    const T r = T(recorded_m) - mu;
    return exp(-r * r / (T(2.0) * var)) / sqrt(T(2.0 * M_PI) * var);
}

/// @brief ln of the probability (error) or density [1/m] (range) of a recorded value, given the
/// surface reading's normal density there (readingDensity at the terms' mean and variance;
/// unused for an error value).
/// @param recorded_m the recorded range, NaN for an error value
/// @param L_m the distance to the surface, @param rmax_m the sensor's maximum range
template <class T>
T logLikelihoodWith(const BeamTerms<T>& x, double recorded_m, double L_m, double rmax_m, const T& normal)
{
    using std::log;
    const T& ps = x.ps;
    const T stop = x.d + (T(1.0) - x.d) * ps;  // P(no surface reading)
    if (std::isnan(recorded_m)) {
        const T err = extended::errorShare(x.d, ps, x.q);
        return log(T(0.5 * kLapse) + T(1.0 - kLapse) * err);
    }
    const T surface = (T(1.0) - stop) * (T(1.0 - kOutlier) * normal + T(kOutlier / rmax_m));
    const T shortr = recorded_m < L_m ? (T(1.0) - x.d) * ps * x.q / T(L_m) : T(0.0);
    return log(T(0.5 * kLapse / rmax_m) + T(1.0 - kLapse) * (surface + shortr));
}

/// @brief ln of the probability (error) or density [1/m] (range) of a recorded value.
/// @param recorded_m the recorded range, NaN for an error value
/// @param L_m the distance to the surface, @param rmax_m the sensor's maximum range
template <class T>
T logLikelihood(const BeamTerms<T>& x, double recorded_m, double L_m, double rmax_m)
{
    if (std::isnan(recorded_m)) return logLikelihoodWith(x, recorded_m, L_m, rmax_m, T(0.0));
    const T mu = extended::rangeMean(x.mu0, x.beta, x.column);
    const T var = extended::rangeVariance(x.sd0, x.gamma, x.column);
    return logLikelihoodWith(x, recorded_m, L_m, rmax_m, readingDensity(recorded_m, mu, var));
}

}  // namespace smokescan
