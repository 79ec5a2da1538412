#pragma once
/// @file target_radiance.hpp
/// @brief The target's converged radiance at an affordable cost. A path-traced pixel in smoke is a
/// heavy-tailed estimate (relative variance 10–50 per sample at the BOCAS threshold), and HSV
/// saturation is non-linear, so per-pixel saturation of a noisy frame is biased (more saturated at
/// fewer samples). The target's patches are flat paper under smooth light in smooth smoke, so each
/// patch's radiance is a smooth field: a polynomial in the pixel coordinates, fitted per patch and
/// channel by least squares to the pixel means (an unbiased estimate of the field at any number of
/// samples, up to its lack of fit, which is measured). Samples go to the target's pixels only, in
/// independent batches until each patch's fitted mean has the relative standard error asked for;
/// the spread between batches also gives the error of anything derived from the field.
///
/// | field        | default | unit | meaning                                                           |
/// |--------------|---------|------|-------------------------------------------------------------------|
/// | meter_spp    | 2       | –    | samples per pixel of the full frame that meters exposure and finds the target |
/// | batch_spp    | 8       | –    | samples per target pixel in one batch                              |
/// | min_batches  | 4       | –    | at least this many batches (the error needs two; four give it 3 degrees of freedom) |
/// | max_batches  | 16      | –    | at most this many                                                  |
/// | rel_error    | 0.03    | –    | stop when every patch's fitted mean radiance has this relative standard error, every channel |
/// | degree       | 4       | –    | total degree of each patch's polynomial field                      |
#include <map>
#include <string>
#include <vector>

#include "smokescan/camera/target_patches.hpp"
#include "smokescan/io/image.hpp"
#include "smokescan/render/renderer.hpp"
#include "smokescan/scene/camera_sensor.hpp"

namespace smokescan {

struct TargetRadianceConfig {
    int meter_spp = 2;
    int batch_spp = 8;
    int min_batches = 4;
    int max_batches = 16;
    double rel_error = 0.03;
    int degree = 4;
};

struct TargetRadiance {
    Image radiance;  ///< the fitted field on the target's pixels (linear RGB), the metering frame elsewhere
    std::vector<Image> batches;  ///< each batch's own fitted field, same layout
    Image ids;  ///< object, material, depth of the first surface, every pixel
    std::vector<int> patch_of_pixel;  ///< index into the target's patch names; −1: not the target
    double exposure = 0;  ///< from the metering frame (meterExposure)
    int spp = 0;  ///< samples per target pixel, all batches
    double rel_error = 0;  ///< achieved: the worst patch and channel
    std::map<std::string, double> lack_of_fit;  ///< per patch: residual variance / noise variance (1: a perfect field)
};

/// @brief Renders the frame of `rc` (its spp and seed are replaced) and the target's converged field.
/// @throw Error when the camera does not see the target or the configuration is out of range.
TargetRadiance measureTargetRadiance(const Scene& scene, const SurfaceSet& surfaces, const RenderConfig& rc,
                                     const TargetPatches& target, const CameraSensor& sensor,
                                     const TargetRadianceConfig& cfg);

}  // namespace smokescan
