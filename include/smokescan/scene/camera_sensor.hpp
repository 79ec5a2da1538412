#pragma once
/// @file camera_sensor.hpp
/// @brief What a scene camera's sensor and pipeline do to the light it receives (a camera's
/// `sensor = { … }` table): exposure, photon shot noise, read noise, full-well clipping, white
/// balance, the sRGB curve and quantisation. camera/develop.hpp applies it.
///
/// | key            | default     | unit | meaning                                                        |
/// |----------------|-------------|------|----------------------------------------------------------------|
/// | exposure       | 0 (auto)    | 1/(W·m⁻²·sr⁻¹) | radiance → fraction of full well, ≤ 1e6; 0: average metering (frame mean luminance → `meter_grey`) |
/// | meter_grey     | 0.18        | –    | in [1e-4, 1]: the fraction of full well the auto exposure puts the frame's mean luminance at |
/// | full_well_e    | 8000        | e⁻   | electrons at saturation (sets the shot noise: σ/μ = 1/√(μ·full_well)) |
/// | read_noise_e   | 10          | e⁻   | read noise, RMS                                                 |
/// | white_balance  | [1, 1, 1]   | –    | gains on R, G, B after the sensor (the renderer's RGB is the balanced space) |
/// | bits           | 8           | –    | output quantisation (0: none, floats)                           |
/// | noise          | true        | –    | false: a noiseless camera (no shot or read noise)               |
///
/// The defaults are a generic webcam of the smoke paper's time (2–3 µm CMOS pixels: a full well of
/// 5–10 ke⁻ and a read noise of 5–15 e⁻ are that class's order of magnitude; 8-bit sRGB output).
/// The paper does not name its camera's sensor: these are stated assumptions, not measurements.
#include <array>

namespace smokescan {

struct CameraSensor {
    double exposure = 0;
    double meter_grey = 0.18;
    double full_well_e = 8000;
    double read_noise_e = 10;
    std::array<double, 3> white_balance{{1.0, 1.0, 1.0}};
    int bits = 8;
    bool noise = true;
};

}  // namespace smokescan
