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
/// | field          | TargetRadianceConfig{} | – | the converged target radiance (target_radiance.hpp): per-pixel saturation of a noisy frame is biased, of a converged one is not |
/// | width, height  | 320, 240  | px   | frame size (the built-in calibration's)                          |
/// | camera         | ""        | –    | scene camera name ("" = the first)                               |
/// | target_prefix  | "target_" | –    | surfaces whose names start with it are the target; the rest of the name is the patch |
/// | seed           | 1         | –    | render seed; frame k renders with seed + k                        |
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "smokescan/camera/saturation.hpp"
#include "smokescan/camera/target_patches.hpp"
#include "smokescan/camera/target_radiance.hpp"
#include "smokescan/scene/scene.hpp"
#include "smokescan/scene/surfaces.hpp"

namespace smokescan {

struct RenderConfig;

/// Saturation statistics of the target in one rendered frame.
struct TargetSaturation {
    SaturationStats all;  ///< every target pixel
    std::map<std::string, SaturationStats> patches;  ///< per patch (name without the prefix)
    double exposure = 0;  ///< auto exposure used
    /// Converged measurement only (0 otherwise): the standard error of each mean saturation
    /// (the camera's noise and the field's, from its batches), the samples per target pixel, the
    /// field's relative error and lack of fit (target_radiance.hpp).
    double se = 0;
    std::map<std::string, double> patch_se;
    int spp = 0;
    double rel_error = 0;
    std::map<std::string, double> lack_of_fit;
    /// The saturation the camera's noise alone gives a grey pixel at the mean exposed level of
    /// the target (floor) and of each patch (develop.hpp: greyNoiseSaturation).
    double floor = 0;
    std::map<std::string, double> patch_floor;
    /// Each patch's mean linear colour (the field's, RGB) and its share of the target's pixels.
    std::map<std::string, std::array<double, 3>> patch_colour;
    std::map<std::string, double> patch_share;
    /// Each patch's pixel brightness: the means of 8 equal-count classes of the field's luminance
    /// over the patch's mean (1 everywhere for an evenly lit, matte patch).
    std::map<std::string, std::vector<double>> patch_brightness;
};

/// @brief Renders `rc` and measures the saturation of the pixels whose first surface is a target
/// surface (name starting with `target_prefix`).
/// @param display receives the frame as the camera delivers it (sRGB, auto exposure), if given.
/// @param ids receives the object id, material id and depth channels, if given.
/// @throw Error when the scene has no target surfaces, or the frame shows none of them.
TargetSaturation measureTargetSaturation(const Scene& scene, const SurfaceSet& surfaces, const RenderConfig& rc,
                                         const std::string& target_prefix, Image* display = nullptr,
                                         Image* ids = nullptr);

/// @brief The converged measurement: the target's radiance field (target_radiance.hpp) through
/// the scene camera's sensor (develop.hpp), then per-pixel HSV saturation of the target's pixels.
/// The camera's noise is the only noise in it; the field's residual noise is in `se`.
/// @param display receives the developed frame, if given. @param ids the id channels, if given.
TargetSaturation measureConvergedSaturation(const Scene& scene, const SurfaceSet& surfaces, const RenderConfig& rc,
                                            const std::string& target_prefix, const TargetRadianceConfig& field,
                                            Image* display = nullptr, Image* ids = nullptr);

struct SaturationRenderConfig {
    TargetRadianceConfig field;
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
    /// @brief The name of the scene camera it renders.
    const std::string& cameraName() const;

private:
    const Scene& scene_;
    const SurfaceSet& surfaces_;
    SaturationRenderConfig cfg_;
};

}  // namespace smokescan
