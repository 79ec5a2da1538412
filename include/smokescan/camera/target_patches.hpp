#pragma once
/// @file target_patches.hpp
/// @brief The coloured target the smoke paper measured smoke by: the scene's surfaces whose names
/// start with a prefix ("target_blue" → patch "blue").
#include <string>
#include <vector>

#include "smokescan/scene/scene.hpp"

namespace smokescan {

/// The target's patches: surfaces named prefix + patch (e.g. "target_blue" → patch "blue").
struct TargetPatches {
    std::vector<std::string> names;  ///< patch names, each once, in scene order
    std::vector<int> patch_of;  ///< scene surface index → index into names; −1: not the target

    /// Patch index of surface `surface` (an object id from a frame's id channel); −1 if none.
    int of(int surface) const
    {
        return surface >= 0 && size_t(surface) < patch_of.size() ? patch_of[size_t(surface)] : -1;
    }
};

/// @brief The surfaces of `scene` whose names start with `prefix`, grouped by the rest of the name.
/// @throw Error naming the scene when no surface name starts with `prefix`.
TargetPatches targetPatches(const Scene& scene, const std::string& prefix);

}  // namespace smokescan
