#pragma once
/// @file lms200.hpp
/// @brief The Sick LMS200: its datasheet spec and its reported error values (the LMS200 manual;
/// docs/references.md, docs/sensors.md). Its kind: src/sensor_config/kinds/lms200.cpp.
#include "smokescan/sensor_config/lrf.hpp"

namespace smokescan {

/// @brief Sick LMS200 reported values (raw, in the range mode's unit): kNoEcho and above are errors.
namespace lms_code {
constexpr long long kNoEcho = 8183;  ///< measured value > maximum (no echo within range)
constexpr long long kWeakOrAmbiguous = 8189;  ///< echo too weak or too wide
constexpr long long kDazzled = 8191;  ///< dazzled
}  // namespace lms_code

/// @brief Sick LMS200: 180° at `resolution_deg` (1 or 0.5), range mode 8 m (mm) or 80 m (cm).
/// @throw Error for another resolution or range mode.
LrfSpec lms200(double resolution_deg = 0.5, double range_mode_m = 8.0);

}  // namespace smokescan
