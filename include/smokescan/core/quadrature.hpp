#pragma once
/// @file quadrature.hpp
/// @brief The expectation over a standard normal Z as an equal-weight average over its
/// quantiles: E[f(Z)] ≈ (1/N) Σ_i f(z_i), z_i = Φ⁻¹((i + ½)/N). Unlike Gauss–Hermite it stays
/// accurate for a step-like f (an onset): the error is at most the step's size / (2N).

namespace smokescan {

constexpr int kNormalNodes = 32;

/// @brief The kNormalNodes quantile nodes z_i = Φ⁻¹((i + ½)/N), ascending (computed once).
const double* normalNodes();

}  // namespace smokescan
