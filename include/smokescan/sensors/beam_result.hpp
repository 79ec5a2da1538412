#pragma once
/// @file beam_result.hpp
/// @brief What one beam reports, and why; the sensor-side rounding every model shares.
#include "smokescan/media/smoke.hpp"
#include "smokescan/scene/surfaces.hpp"
#include "smokescan/sensor_config/lrf.hpp"

namespace smokescan {

/// What one beam reports, and why.
struct BeamResult {
    long long value = 0;  ///< reported value in the sensor's unit: a range or an error code
    bool error = false;  ///< value is an error code
    double true_range_m = kInf;  ///< noiseless distance of what was measured (surface or smoke)
    SurfaceHit hit;  ///< first surface in clear air (up to the sensor's maximum range)
    BeamSmoke smoke;  ///< smoke met up to the surface (or maximum range)
    const char* cause = "ok";  ///< why: "ok", or the error's cause (docs/sensors.md)
    double power = 0;  ///< physical model: received amplitude (normalised power)
};

/// @brief Marks r as an error: `code` in the sensor's unit, and why.
BeamResult& markError(BeamResult& r, long long code, const char* cause);

/// @brief Reports a measured distance the way the sensor does: outside its window → its no-return
/// value; else range_m plus the datasheet noise (`noise` a standard normal), rounded to the unit,
/// again refused when that lands on an error value. Shared by the paper and physical models.
BeamResult& reportRange(const LrfSpec& spec, double range_m, double noise, BeamResult& r);

/// @brief Probability that reportRange gives an error value for a true range_m: outside the
/// window, or the datasheet noise carrying the rounded value onto an error value.
double reportErrorProbability(const LrfSpec& spec, double range_m);

}  // namespace smokescan
