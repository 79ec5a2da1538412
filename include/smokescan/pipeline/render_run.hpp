#pragma once
/// @file render_run.hpp
/// @brief One camera frame of a scene through its smoke as a library call: what `smokescan
/// render` does at each time, without its files.
///
/// | field    | default        | unit | meaning                                                      |
/// |----------|----------------|------|--------------------------------------------------------------|
/// | render   | RenderConfig's | –    | time, camera, size, spp, seed, depth (render/renderer.hpp)   |
/// | exposure | 0              | –    | the display frame's radiance scale; <= 0: auto (average metering to 18 % grey, an omni camera's over its mirror disc) |
#include "smokescan/pipeline/run_control.hpp"
#include "smokescan/render/renderer.hpp"

namespace smokescan {

struct RenderRunConfig {
    RenderConfig render;
    double exposure = 0;
};

struct RenderedFrame {
    RenderResult result;  ///< linear radiance [W/(m²·sr)], its variance, the id and depth AOVs
    Image display;  ///< what the camera delivers: radiance × exposure, clipped, sRGB-encoded in [0, 1]
    double exposure = 0;  ///< the scale the display frame used
    Camera camera;  ///< the scene's camera at the frame's time, at the size rendered
};

/// @brief Renders one frame. With a control, the frame's tiles are rendered on other threads
/// while the calling thread reports progress (tiles done of total) and asks cancel about every
/// 50 ms; the control is only ever called on the calling thread.
/// @throw Error as render() does; Cancelled when the control stopped it
RenderedFrame renderFrame(const Scene& scene, const SurfaceSet& surfaces, const RenderRunConfig& cfg,
                          const RunControl& control = {});

}  // namespace smokescan
