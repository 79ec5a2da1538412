#pragma once
/// @file renderer.hpp
/// @brief Physically based frames of a scene through its smoke: a volumetric path tracer over
/// Embree surfaces and the scene's OpenVDB smoke (docs/renderer.md).
///
/// | field          | default | unit | meaning                                                   |
/// |----------------|---------|------|-----------------------------------------------------------|
/// | time_s         | 0       | s    | scene time (smoke timelines, plumes)                      |
/// | spp            | 16      | –    | samples per pixel                                         |
/// | seed           | 1       | –    | image is a pure function of (scene, config, seed)         |
/// | max_depth      | 256     | –    | scattering and bounce events per path (32 lost 2.6 % of the light in the densest calibration smoke; 256 loses none measurable) |
/// | rr_depth       | 4       | –    | events before Russian roulette starts                     |
/// | camera         | ""      | –    | scene camera name ("" = the first)                        |
/// | width, height  | 0       | px   | override the camera's resolution (0 = keep)               |
/// | majorant_cells | 32      | –    | majorant grid cells along the smoke's longest axis        |
/// | progress       | true    | –    | progress bar and ETA on stderr, only when it is a terminal |
/// | segment_lighting | true  | –    | the lights' in-scattered light along each path segment (equiangular + forced collision, MIS) instead of at collisions |
/// | mask           | null    | –    | pixels to render (width × height, row-major, non-zero = render); the rest stay 0. Ids are made for every pixel |
/// | split_primary  | false   | –    | camera rays: the surface through the smoke's transmittance plus a forced collision in the smoke |
/// | watch          | null    | –    | counts finished tiles and lets another thread stop the render (RenderWatch) |
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "smokescan/io/image.hpp"
#include "smokescan/render/camera.hpp"
#include "smokescan/scene/scene.hpp"
#include "smokescan/scene/surfaces.hpp"

namespace smokescan {

/// What another thread may watch and ask of a render in progress: the frame is rendered in
/// tiles of 16 × 16 px; once `stop` turns true, no pixel begins its samples (the ids are still
/// made) and tiles not yet begun are skipped.
struct RenderWatch {
    std::atomic<long long> tiles_total{0};  ///< set when the render starts
    std::atomic<long long> tiles_done{0};
    std::atomic<bool> stop{false};
};

struct RenderConfig {
    double time_s = 0;
    int spp = 16;
    uint64_t seed = 1;
    int max_depth = 256;
    int rr_depth = 4;
    std::string camera;
    int width = 0, height = 0;
    int majorant_cells = 32;
    bool progress = true;
    bool segment_lighting = true;
    const std::vector<uint8_t>* mask = nullptr;
    bool split_primary = false;  // measured: no gain on top of segment_lighting (docs/performance.md)
    RenderWatch* watch = nullptr;
};

struct RenderResult {
    Image radiance;  ///< linear RGB radiance [W/(m²·sr)], mean over samples
    Image variance;  ///< per pixel and channel, variance of that mean (sample variance / spp)
    Image ids;  ///< channels object, material (−1: none), depth [m] of the first surface
    double seconds = 0;
    long long samples = 0;
    bool stopped = false;  ///< the watch stopped it: some tiles were skipped (their pixels are 0)
};

/// @brief Renders the scene's camera at config.time_s. @throw Error for a scene without a
/// camera, an unknown camera name, a zero resolution, spp < 1 or a non-finite pose.
RenderResult render(const Scene& scene, const SurfaceSet& surfaces, const RenderConfig& cfg);

/// @brief Renders through an explicit camera model (any projection).
RenderResult render(const Scene& scene, const SurfaceSet& surfaces, const CameraModel& camera, const RenderConfig& cfg);

/// @brief What a video camera delivers: linear radiance × exposure, clipped to [0, 1], encoded
/// with the sRGB transfer curve (8-bit quantisation happens when writing a PNG/JPEG/TIFF).
/// @param exposure the scale applied to radiance; <= 0 chooses it automatically by average
/// metering (the frame's mean luminance maps to 18 % grey), as a camera's auto exposure would.
/// @param used receives the scale used (optional).
/// @param metered_by when given, metering averages only the pixels whose centre this camera sees
/// through (an omni camera's mirror disc, not the black frame around it and the robot's base).
Image toDisplay(const Image& radiance, double exposure, double* used = nullptr,
                const CameraModel* metered_by = nullptr);

/// sRGB transfer function (linear [0,1] → encoded [0,1]).
double srgbEncode(double linear);

}  // namespace smokescan
