#pragma once
// Internal: the TOML tables of a sensor's models, shared by scene files and sensor files.
// Each parameter set reads and writes its own keys from one registry (sensor_tables.cpp).
#include <ostream>

#include "smokescan/sensor_config/sensor_config.hpp"
#include "toml_reader.hpp"

namespace smokescan {

/// Reads the optional keys of a [physical] table into p and validates them.
/// The [physical] table of a sensor of `type`: its receiver's keys only, each within its bounds.
void readPhysicalTable(TomlTable t, PhysicalParams& p, SensorType type);
/// Writes every PhysicalParams field as `key = value` lines.
void writePhysicalTable(std::ostream& o, const PhysicalParams& p, SensorType type);
/// Reads the optional keys of a [paper] table.
void readPaperTable(TomlTable t, PaperModelConfig& p);
/// Writes the paper model's keys as `key = value` lines.
void writePaperTable(std::ostream& o, const PaperModelConfig& p);
/// Reads an [extensions] table (sensors/extensions.hpp) into e and validates it.
void readExtensionsTable(TomlTable t, ModelExtensions& e);
/// Writes the extensions as an [extensions] section with its surface and sector tables.
void writeExtensionsTable(std::ostream& o, const ModelExtensions& e);
/// Reads a sensor model name at `key` ("paper" or "physical"); absent keeps `def`.
SensorModel readSensorModel(TomlTable& t, const char* key, SensorModel def);
/// Reads a scene's `[[sensor]]` keys beyond name, pose and sensor_file, in the scene format:
/// model, penetration_power, local_threshold, [physical], resolution_deg, range_mode_m.
void readSceneSensorKeys(TomlTable& t, SensorConfig& c);

}  // namespace smokescan
