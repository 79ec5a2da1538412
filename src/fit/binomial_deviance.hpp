#pragma once
// The signed deviance residual of a binomial count, shared by the fits that maximise a binomial
// likelihood with Ceres: the squares of sign(e − n·p)·√d sum to the deviance, so least squares on
// them is maximum likelihood, and Levenberg–Marquardt on a fixed objective cannot two-cycle the
// way Fisher scoring (Gauss–Newton with weights frozen per round) can.
#include <cmath>

namespace smokescan::detail {

/// The value of a double or of a Ceres Jet (its scalar part `a`).
inline double scalar(double x) { return x; }
template <class J>
double scalar(const J& j)
{
    return j.a;
}

/// @brief The two tails of a probit (normal CDF) or logistic link at z: p = F(z) and q = F(−z),
/// each computed as its own tail (1 − p loses every digit where p → 1). A tail that underflowed
/// (a trial step far out) is held at 1e-300: the deviance stays finite, with no gradient there.
template <class T>
void tails(const T& z, bool logistic, T& p, T& q)
{
    using std::erfc;
    using std::exp;
    if (logistic) {
        p = T(1) / (T(1) + exp(-z));
        q = T(1) / (T(1) + exp(z));
    } else {
        p = T(0.5) * erfc(-z / T(M_SQRT2));
        q = T(0.5) * erfc(z / T(M_SQRT2));
    }
    const double tiny = 1e-300;
    if (!(scalar(p) > tiny)) p = T(tiny);
    if (!(scalar(q) > tiny)) q = T(tiny);
}

/// @brief sign(e − n·p)·√d with d = 2[e·ln(e/(n·p)) + (n − e)·ln((n − e)/(n·q))].
/// @param p, q the event's probability and its complement, each computed as its own tail by the
///        caller (1 − p loses every digit where p → 1); both must be > 0
/// Near d = 0, where √d has no derivative, the Pearson residual (e − n·p)/√(n·p·q) stands in: it
/// has the same value and slope there.
template <class T>
T signedDeviance(double n, double e, const T& p, const T& q)
{
    using std::log;
    using std::sqrt;
    T d(0);
    if (e > 0) d += T(e) * (std::log(e / n) - log(p));
    if (e < n) d += T(n - e) * (std::log((n - e) / n) - log(q));
    d *= T(2);
    if (!(scalar(d) > 1e-20)) return (T(e) - T(n) * p) / sqrt(T(n) * p * q);
    return e > n * scalar(p) ? sqrt(d) : -sqrt(d);
}

}  // namespace smokescan::detail
