#pragma once
/// @file light_mixing.hpp
/// @brief What the smoke does to the target's light, measured from the patches' converged linear
/// colours rather than from their saturation: at each density, one transmittance T and one
/// scattered-light colour A (RGB) such that every patch reads x_p = l_p·T + A·(1 − T) (Koschmieder
/// for each channel), l_p the patch's clear-air colour. No curve and no camera enter it, so it checks
/// the saturation curves' parameters independently: −ln T / ρ is the extinction × path (b), and A's
/// colour against density is the scattered light's drift.
#include <array>
#include <utility>
#include <vector>

namespace smokescan {

struct LightMixing {
    double density = 0;
    double transmittance = 1;  ///< T, least squares over every patch and channel (Ceres)
    double transmittance_se = 0;  ///< its standard error, from the residuals' scatter
    std::array<double, 3> scattered{{0, 0, 0}};  ///< A [W·m⁻²·sr⁻¹ per channel, the renderer's RGB]
    double rms = 0;  ///< r.m.s. residual of the x_p over patches and channels, relative to their mean
};

/// @brief T and A at one density from the patches' clear-air colours `clear[p]` and their colours
/// `seen[p]` there (same order, at least two patches): T and A minimise Σ (x − l·T − A·(1 − T))²
/// over patches and channels (Ceres). @throw Error for fewer than two patches or sizes that differ.
LightMixing measureLightMixing(double density, const std::vector<std::array<double, 3>>& clear,
                               const std::vector<std::array<double, 3>>& seen);

/// @brief b and its standard error from −ln T = b·ρ through the origin, weighted by T's errors,
/// over the densities whose T lies in [0.02, 0.98]; (0, 0) when none does.
std::pair<double, double> extinctionPath(const std::vector<LightMixing>& m);

}  // namespace smokescan
