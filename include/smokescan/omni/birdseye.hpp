#pragma once
/// @file birdseye.hpp
/// @brief A bird's-eye view of the floor from an omni frame (Nayar's equations, the omnicam
/// paper's Eqs. 1–3): each output pixel is a floor point; its omni pixel is found by projecting it
/// through the camera, and the frame is sampled there (bilinear).
///
/// | parameter     | default | unit | meaning                                                  |
/// |---------------|---------|------|----------------------------------------------------------|
/// | size_px       | 800     | px   | the square view's side                                   |
/// | metres_per_px | 0.01    | m    | floor distance per output pixel                          |
/// | height_m      | –       | m    | the viewpoint's height above the floor                   |
///
/// The view is centred below the viewpoint, the camera's local +x to the right and +y up, as
/// the omni image. Floor points the camera does not see (beyond its rim, on its base, at or above
/// its horizon) are black. Points off the floor (walls, objects) are drawn where their rays meet
/// the floor, stretched outwards, as in the paper's Fig. 1.
#include "smokescan/io/image.hpp"
#include "smokescan/render/omni_camera.hpp"

namespace smokescan {

struct BirdseyeConfig {
    int size_px = 800;
    double metres_per_px = 0.01;
    double height_m = 0.931;
};

/// @throw Error for a size outside 1…16384, a scale or height that is not finite and > 0, or a
/// frame of another size than the camera's.
Image birdseye(const Image& frame, const OmniCamera& cam, const BirdseyeConfig& cfg);

}  // namespace smokescan
