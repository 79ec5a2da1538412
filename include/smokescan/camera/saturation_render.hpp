#pragma once
/// @file saturation_render.hpp
/// @brief The target saturation a camera measures, by rendering its frame: the scene's smoke at the
/// frame's time, the physically based renderer, the camera's auto exposure and sRGB encoding, and
/// the HSV saturation of the target's pixels (found from the object-id channel, as the calibration
/// does). The expensive but honest alternative to SaturationPredictor: it sees what the camera
/// sees (inhomogeneous smoke, plumes, the lamp's light), not a column read through the curve.
///
/// | field          | default   | unit | meaning                                                         |
/// |----------------|-----------|------|-----------------------------------------------------------------|
/// | spp            | 4         | –    | samples per pixel (the built-in calibration's: per-pixel noise raises HSV saturation, so keep the curve's) |
/// | width, height  | 320, 240  | px   | frame size (the built-in calibration's)                          |
/// | camera         | ""        | –    | scene camera name ("" = the first)                               |
/// | target_prefix  | "target_" | –    | surfaces whose names start with it are the target; the rest of the name is the patch |
/// | seed           | 1         | –    | render seed; frame k renders with seed + k                        |
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "smokescan/camera/saturation.hpp"
#include "smokescan/scene/scene.hpp"
#include "smokescan/scene/surfaces.hpp"

namespace smokescan {

struct RenderConfig;

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

/// Saturation statistics of the target in one rendered frame.
struct TargetSaturation {
    SaturationStats all;  ///< every target pixel
    std::map<std::string, SaturationStats> patches;  ///< per patch (name without the prefix)
    double exposure = 0;  ///< auto exposure used
};

/// @brief Renders `rc` and measures the saturation of the pixels whose first surface is a target
/// surface (name starting with `target_prefix`).
/// @param display receives the frame as the camera delivers it (sRGB, auto exposure), if given.
/// @param ids receives the object id, material id and depth channels, if given.
/// @throw Error when the scene has no target surfaces, or the frame shows none of them.
TargetSaturation measureTargetSaturation(const Scene& scene, const SurfaceSet& surfaces, const RenderConfig& rc,
                                         const std::string& target_prefix, Image* display = nullptr,
                                         Image* ids = nullptr);

struct SaturationRenderConfig {
    int spp = 4;
    int width = 320, height = 240;
    std::string camera;
    std::string target_prefix = "target_";
    uint64_t seed = 1;
};

/// @brief Frames of one scene camera at scene times, measured. Keeps references to the scene and
/// its surfaces: both must outlive it.
class SaturationRenderer {
public:
    /// @throw Error for a bad configuration, no such camera, or a camera that does not see the
    /// target (checked by rendering a 1-spp frame of the scene at t_check_s).
    SaturationRenderer(const Scene& scene, const SurfaceSet& surfaces, const SaturationRenderConfig& cfg,
                       double t_check_s = 0);
    /// @param frame index k: the frame renders with seed cfg.seed + k.
    /// @param display, ids receive the frame and its id channels, if given.
    TargetSaturation measure(double time_s, uint64_t frame, Image* display = nullptr, Image* ids = nullptr) const;

private:
    const Scene& scene_;
    const SurfaceSet& surfaces_;
    SaturationRenderConfig cfg_;
};

}  // namespace smokescan
