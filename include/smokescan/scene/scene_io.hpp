#pragma once
/// @file scene_io.hpp
/// @brief Reading scenes from TOML (files or built-in names).
#include <string>
#include <vector>

#include "smokescan/scene/scene.hpp"

namespace smokescan {

/// @brief Loads a scene: a built-in name (see builtinSceneNames()) or a path to a .toml file.
/// @throw Error "FILE:LINE: problem" for unknown keys, wrong types, missing fields, bad values.
Scene loadScene(const std::string& name_or_path);

/// @brief Parses scene TOML text; `source` names it in errors; relative paths in the scene
/// (OBJ, VDB) are resolved against `base_dir`.
Scene parseScene(const std::string& text, const std::string& source, const std::string& base_dir);

/// @brief The files a loaded scene read besides its own: meshes, .vdb grids, sensor files (a
/// command records them as inputs, so that no output replaces them).
std::vector<std::string> sceneFiles(const Scene& scene);

std::vector<std::string> builtinSceneNames();
/// The TOML text of a built-in scene; throws Error for an unknown name.
std::string builtinSceneText(const std::string& name);

}  // namespace smokescan
