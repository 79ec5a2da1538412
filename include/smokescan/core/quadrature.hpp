#pragma once
/// @file quadrature.hpp
/// @brief The expectation over a standard normal Z as an equal-weight average over its
/// quantiles: E[f(Z)] ≈ (1/N) Σ_i f(z_i), z_i ∝ Φ⁻¹((i + ½)/N), scaled to unit variance (the raw
/// quantiles' is 0.96 at N = 32). Unlike Gauss–Hermite it stays accurate for a step-like f (an
/// onset): the error is about the step's size / (2N).

namespace smokescan {

constexpr int kNormalNodes = 32;

/// @brief The kNormalNodes nodes, ascending, symmetric, of unit variance (computed once).
const double* normalNodes();

}  // namespace smokescan
