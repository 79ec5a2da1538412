#pragma once
/// @file sensor_kind.hpp
/// @brief The kinds of laser range finder and of sensor model smokescan simulates, and each
/// sensor's error values by name. Names are parsed once, where a file or option is read; the rest
/// of the code switches on the enums.
///
/// | type      | model      | implementation (sensors/beam_model.hpp)                      |
/// |-----------|------------|--------------------------------------------------------------|
/// | urg04lx   | paper      | the smoke paper's penetration-power rule                      |
/// | urg04lx   | physical   | AMCW phase measurement of the lidar-equation echoes          |
/// | lms200    | paper      | the smoke paper's rule: local smoke is an obstacle           |
/// | lms200    | physical   | pulsed time of flight, first echo of the waveform            |
#include <optional>
#include <string>

namespace smokescan {

/// @brief A laser range finder of the smoke paper.
enum class SensorType { Urg04lx, Lms200 };
/// @brief How a beam's reading is made from the scene: the paper's rules or the lidar equation.
enum class SensorModel { Paper, Physical };

/// @brief The name used in scene and sensor files ("urg04lx", "lms200").
const char* sensorTypeName(SensorType t);
/// @brief The name used in files and options ("paper", "physical").
const char* sensorModelName(SensorModel m);
/// @brief The type for a name, or nothing for an unknown one.
std::optional<SensorType> parseSensorType(const std::string& name);
/// @brief The model for a name, or nothing for an unknown one.
std::optional<SensorModel> parseSensorModel(const std::string& name);
/// @brief "urg04lx or lms200": the accepted names, for messages.
const char* sensorTypeNames();
/// @brief "paper or physical".
const char* sensorModelNames();

/// @brief Hokuyo URG-04LX reported values (SCIP 2.0): values below kFirstRange are errors.
namespace urg_code {
constexpr long long kNoReturn = 0;  ///< nothing in range (also: the paper model's smoke error)
constexpr long long kLowIntensity = 1;  ///< signal too weak
constexpr long long kTwoWaveDifference = 8;  ///< the two modulation waves disagree in amplitude
constexpr long long kStrongReflection = 18;  ///< receiver saturated
constexpr long long kFirstRange = 20;  ///< smallest range value [mm]
}  // namespace urg_code

/// @brief Sick LMS200 reported values (raw, in the range mode's unit): kNoEcho and above are errors.
namespace lms_code {
constexpr long long kNoEcho = 8183;  ///< measured value > maximum (no echo within range)
constexpr long long kWeakOrAmbiguous = 8189;  ///< echo too weak or too wide
constexpr long long kDazzled = 8191;  ///< dazzled
}  // namespace lms_code

}  // namespace smokescan
