#pragma once
/// @file extensions.hpp
/// @brief What a diagnosis learned about a sensor, beyond the paper model: the accepted candidate
/// extensions (docs/diagnosis.md), kept in a sensor file's `[extensions]` section and simulated by
/// `smokescan scan` in the URG-04LX's models (the paper model: sensors/urg04lx/paper_urg.cpp; the
/// physical model: sensors/extension_rule.cpp, where a moved threshold scales the smoke the
/// receiver sees). Default-constructed: today's model, nothing extended.
///
/// A beam at regional smoke column C [density·m] along it, to a surface at L [m]:
///  1. in a dropout sector it fails with probability d, whatever the smoke;
///  2. else the smoke stops it when ln C > ln P' + w·z, z a standard normal draw, where
///     ln P' = ln P + threshold_factor(surface) ∓ hysteresis/2 (− while the smoke rises);
///     a stopped beam returns a short range, uniform on (0, L), with probability q, else error 0;
///  3. else it reads N(L·(1 + β(surface)·C), σ₀(L)² + (γ·C)²), σ₀ the datasheet noise.
///
/// | key (sensor file)          | default | unit          | meaning                                    |
/// |----------------------------|---------|---------------|--------------------------------------------|
/// | clock_offset_s             | 0       | s             | camera clock − laser clock (the recording's, not the sensor's: `scan --camera-offset` and `diagnose --offset` default to it) |
/// | threshold_width            | 0.02    | ln(column)    | w: the onset's spread (0.02 is a step for the data) |
/// | range_noise_growth_m       | 0       | m/(density·m) | γ                                          |
/// | smoke_obstacle_return      | 0       | –             | q                                          |
/// | hysteresis                 | 0       | –             | ln P(falling) − ln P(rising)               |
/// | [[extensions.surface]] name, threshold_factor, range_bias | 0, 0 | –, 1/(density·m) | ln(P_surface/P) and β of a named surface |
/// | [[extensions.sector]] from_deg, to_deg, dropout | – | deg, deg, – | beams at angles in [from, to] fail with probability d |
#include <map>
#include <string>
#include <vector>

namespace smokescan {

/// The width of the paper model's step in ln(column) when extended: a 2 % blur, a step for the data.
constexpr double kBaseWidth = 0.02;

/// One surface's extensions.
struct SurfaceExtension {
    double threshold_factor = 0;  ///< ln(P_surface / P)
    double range_bias = 0;  ///< β [1/(density·m)]: the surface reads L·(1 + β·C)
};

/// One angular sector's dropout.
struct SectorExtension {
    double from_deg = 0, to_deg = 0;  ///< beam angles in the sensor's convention [deg]
    double dropout = 0;  ///< probability that a beam in the sector fails
};

/// The learned extensions of a sensor's paper model.
struct ModelExtensions {
    double clock_offset_s = 0;
    double threshold_width = kBaseWidth;
    double range_noise_growth_m = 0;
    double smoke_obstacle_return = 0;
    double hysteresis = 0;
    std::map<std::string, SurfaceExtension> surfaces;  ///< by scene surface name
    std::vector<SectorExtension> sectors;

    /// @brief Whether any extension changes a beam (the clock offset does not: it is the recording's).
    bool changesBeams() const
    {
        return threshold_width != kBaseWidth || range_noise_growth_m != 0 || smoke_obstacle_return != 0 ||
            hysteresis != 0 || !surfaces.empty() || !sectors.empty();
    }
};

}  // namespace smokescan
