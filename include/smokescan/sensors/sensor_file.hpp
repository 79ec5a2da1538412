#pragma once
/// @file sensor_file.hpp
/// @brief Sensor files: a sensor's model and parameters in TOML, used by `scan --sensor-file`,
/// by a scene's `sensor_file = "…"`, and written by `smokescan fit` and `smokescan diagnose`.
/// Format: docs/sensors.md; the `[extensions]` section: sensors/extensions.hpp.
///
/// ```toml
/// type = "urg04lx"          # must match the sensor it is applied to
/// model = "physical"        # optional: paper | physical
/// [paper]                   # optional: penetration_power [density·m], local_threshold [density]
/// [physical]                # optional: any PhysicalParams field by name (physical_params.hpp)
/// [extensions]              # optional: what a diagnosis learned (extensions.hpp); replaces any
///                           # extensions the config had (a learned model is one whole)
/// ```
#include <string>

#include "smokescan/sensors/sensor_config.hpp"

namespace smokescan {

/// @brief Reads a sensor file and applies it to `config` (fields absent keep their values).
/// @throw Error "FILE:LINE: problem" for unreadable files, unknown keys, bad values, or a type
/// that differs from the config's.
void applySensorFile(const std::string& path, SensorConfig& config);
/// @brief The same from the file's text; `path` names it in errors.
void applySensorText(const std::string& text, const std::string& path, SensorConfig& config);

/// @brief Writes the config's model and every parameter as a sensor file (atomically).
void writeSensorFile(const std::string& path, const SensorConfig& config, const std::string& comment = "");

}  // namespace smokescan
