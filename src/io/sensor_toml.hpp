#pragma once
// Internal: the [paper] and [physical] tables shared by scene files and sensor files.
#include "smokescan/scene/scene.hpp"
#include "toml_reader.hpp"

namespace smokescan {

/// Reads the optional keys of a [physical] table into p and validates them.
void readPhysicalTable(TomlTable t, PhysicalParams& p);
/// Reads the optional keys of a [paper] table into the mount.
void readPaperTable(TomlTable t, SensorMount& m);

}  // namespace smokescan
