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

#include "smokescan/sensor_config/sensor_config.hpp"

namespace smokescan {

/// @brief Reads a sensor file and applies it to `config` (fields absent keep their values).
/// @throw Error "FILE:LINE: problem" for unreadable files, unknown keys, bad values, or a type
/// that differs from the config's.
void applySensorFile(const std::string& path, SensorConfig& config);
/// @brief The same from the file's text; `path` names it in errors.
void applySensorText(const std::string& text, const std::string& path, SensorConfig& config);

/// @brief Writes the config's model and every parameter as a sensor file (atomically).
void writeSensorFile(const std::string& path, const SensorConfig& config, const std::string& comment = "");

/// The omnicam rangefinder's sensor file (`type = "omnicam"`, written by `fit --sensor-type
/// omnicam` and `diagnose`): its smoke onset as the paper model's penetration power along the
/// camera's line of sight, and what a diagnosis learned. No laser model reads it.
///
/// | key                       | default | unit      | meaning                                      |
/// |---------------------------|---------|-----------|----------------------------------------------|
/// | camera                    | ""      | –         | the scene's omni camera it was fitted for     |
/// | tolerance_m               | 0.3     | m         | a reading this far off its truth failed       |
/// | max_range_m               | 3.8     | m         | the rangefinder's maximum range               |
/// | floor_z_m                 | 0       | m         | the floor's height                            |
/// | [paper] penetration_power | –       | density·m | the column at which half its readings fail    |
/// | [extensions]              | –       | –         | as a laser's (extensions.hpp; sectors in bearings on from the first scanline) |
struct OmniSensorFile {
    std::string path;  ///< the file it was read from ("" when made in memory)
    std::string camera;
    double tolerance_m = 0.3, max_range_m = 3.8, floor_z_m = 0;
    double penetration_power = 0;
    ModelExtensions extensions;
};

/// @brief Reads an omnicam sensor file. @throw Error "FILE:LINE: problem" for unknown keys, bad
/// values, another type, or a penetration power that is not positive.
OmniSensorFile readOmniSensorFile(const std::string& path);
/// @brief Writes one (atomically).
void writeOmniSensorFile(const std::string& path, const OmniSensorFile& f, const std::string& comment = "");

}  // namespace smokescan
