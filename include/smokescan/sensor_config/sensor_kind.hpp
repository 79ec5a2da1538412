#pragma once
/// @file sensor_kind.hpp
/// @brief The kinds of laser range finder and of sensor model smokescan simulates. Names are
/// parsed once, where a file or option is read; what differs between kinds is asked of the kind
/// (sensor_config/laser_kind.hpp), each in its own file, its error values in its own header
/// (sensor_config/urg04lx.hpp, lms200.hpp).
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

/// @brief A laser range finder of the smoke paper (a LaserKind each, in this order).
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

}  // namespace smokescan
