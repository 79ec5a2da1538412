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
#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace smokescan {

/// The width of the paper model's step in ln(column) when extended: a 2 % blur, a step for the data.
constexpr double kBaseWidth = 0.02;

/// The values an extension can take: a sensor file's reader refuses values outside them
/// (sensor_tables.cpp) and the diagnosis refuses to report a fit beyond them
/// (diagnose/causes.cpp), so that every finding can be written and simulated.
struct ExtensionBound {
    double lo, hi;
    bool contains(double v) const { return v >= lo && v <= hi; }
};
namespace extension_bounds {
constexpr ExtensionBound kClockOffset_s{-1e5, 1e5};
constexpr ExtensionBound kThresholdWidth{1e-9, 5};  ///< ln(column)
constexpr ExtensionBound kNoiseGrowth_m{0, 1e3};  ///< m per density·m
constexpr ExtensionBound kShare{0, 1};  ///< smoke_obstacle_return, a sector's dropout
constexpr ExtensionBound kLnFactor{-10, 10};  ///< hysteresis, a surface's threshold_factor
constexpr ExtensionBound kRangeBias{-1e4, 1e4};  ///< 1/(density·m)
constexpr ExtensionBound kSectorAngle_deg{-360, 360};
}  // namespace extension_bounds

/// One surface's extensions.
struct SurfaceExtension {
    double threshold_factor = 0;  ///< ln(P_surface / P)
    double range_bias = 0;  ///< β [1/(density·m)]: the surface reads L·(1 + β·C)
};

/// One angular sector's dropout.
struct SectorExtension {
    double from_deg = 0, to_deg = 0;  ///< beam angles in the sensor's convention [deg]
    double dropout = 0;  ///< probability that a beam in the sector fails

    /// @brief Whether a beam at `angle_deg` lies in the sector, on the circle: a sector of the
    /// omnicam's may be given anywhere round it (300…360° or −60…0°); a laser's sectors lie within
    /// its field, where this is the plain interval.
    bool contains(double angle_deg) const
    {
        const double from_start = angle_deg - from_deg - 360 * std::floor((angle_deg - from_deg) / 360);
        return from_start <= to_deg - from_deg + 1e-10;
    }
};

/// The learned extensions of a sensor's paper model: what `scan` simulates, what a sensor file
/// keeps and what the diagnosis fits (its model, a finding at a time).
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
    /// @brief Whether every value lies within its bound (extension_bounds).
    bool withinBounds() const;
    /// @brief The probability that a beam at `angle_deg` drops out: its sectors' together.
    double dropoutAt(double angle_deg) const;
    /// @brief ln(P'/P), the threshold's shift on a surface (null: none of its own) while the
    /// smoke rises or not: the surface's factor and the hysteresis' half, − while it rises.
    double thresholdShift(const SurfaceExtension* surface, bool rising) const
    {
        return (surface ? surface->threshold_factor : 0.0) + (rising ? -0.5 : 0.5) * hysteresis;
    }
};

/// The extensions' effect on one beam, written once for the simulation (sensors) and the
/// diagnosis's likelihood (diagnose/predictive.hpp); T a double or a Ceres Jet.
namespace extended {
/// @brief P(the smoke stops the beam) at ln C (a column C > 0 [density·m]) under the paper
/// model's threshold ln P' and onset width w: Φ((ln C − ln P')/w).
template <class T>
T stopProbabilityLn(const T& ln_column, const T& lnP, const T& width)
{
    using std::erfc;
    return T(0.5) * erfc(-(ln_column - lnP) / width / T(M_SQRT2));
}
/// @brief The same at the column C itself (0 where C ≤ 0: no smoke stops nothing).
template <class T>
T stopProbability(const T& column, const T& lnP, const T& width)
{
    using std::log;
    return column > T(0.0) ? stopProbabilityLn(log(column), lnP, width) : T(0.0);
}
/// @brief P(error value): the dropout d, else the smoke's stop p_s unless it reads short (q).
template <class T>
T errorShare(const T& d, const T& stop, const T& q)
{
    return d + (T(1.0) - d) * stop * (T(1.0) - q);
}
/// @brief The surface reading's mean [m]: L·(1 + β·C).
template <class T>
T rangeMean(const T& L_m, const T& beta, const T& column)
{
    return L_m * (T(1.0) + beta * column);
}
/// @brief Its variance [m²]: σ₀² + (γ·C)².
template <class T>
T rangeVariance(const T& sd0_m, const T& gamma, const T& column)
{
    return sd0_m * sd0_m + gamma * gamma * column * column;
}
}  // namespace extended

}  // namespace smokescan
