#pragma once
/// @file urg04lx.hpp
/// @brief The Hokuyo URG-04LX: its datasheet spec and its reported error values (SCIP 2.0;
/// docs/references.md, docs/sensors.md). Its kind: src/sensor_config/kinds/urg04lx.cpp.
#include "smokescan/sensor_config/lrf.hpp"

namespace smokescan {

/// @brief Hokuyo URG-04LX reported values (SCIP 2.0): values below kFirstRange are errors.
namespace urg_code {
constexpr long long kNoReturn = 0;  ///< nothing in range (also: the paper model's smoke error)
constexpr long long kLowIntensity = 1;  ///< signal too weak
constexpr long long kTwoWaveDifference = 8;  ///< the two modulation waves disagree in amplitude
constexpr long long kStrongReflection = 18;  ///< receiver saturated
constexpr long long kFirstRange = 20;  ///< smallest range value [mm]
}  // namespace urg_code

/// @brief Hokuyo URG-04LX (SCIP 2.0): steps 44…725, 20…5600 mm, error values below 20.
LrfSpec urg04lx();

}  // namespace smokescan
