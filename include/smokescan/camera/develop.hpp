#pragma once
/// @file develop.hpp
/// @brief From linear radiance to the frame a camera delivers, as its sensor and pipeline would
/// (scene/camera_sensor.hpp has the parameters): exposure to a fraction of the full well, photon
/// shot noise (Poisson), read noise (Gaussian), clipping at the full well, white balance, the sRGB
/// curve and quantisation. Saturation measured on its output carries the camera's noise, as the
/// smoke paper's measurement did.
#include <cstdint>

#include "smokescan/io/image.hpp"
#include "smokescan/scene/camera_sensor.hpp"

namespace smokescan {

/// @brief The exposure [fraction of full well per unit radiance]: the sensor's fixed value, or
/// average metering, which puts the frame's mean luminance (Rec. 709 weights) at `meter_grey`.
/// @param radiance linear RGB [W/(m²·sr)]; any number of samples per pixel (only its mean counts)
double meterExposure(const Image& radiance, const CameraSensor& sensor);

/// @brief The encoded frame ([0, 1] per channel; multiples of 1/(2^bits − 1) when quantised).
/// @param radiance linear RGB [W/(m²·sr)]
/// @param exposure from meterExposure
/// @param seed the noise's stream: pixel (x, y) and channel c draw from (seed, pixel, c), so a
///        frame is the same for a seed whatever the thread count
Image develop(const Image& radiance, const CameraSensor& sensor, double exposure, uint64_t seed);

/// @brief The mean HSV saturation the camera's noise gives a grey pixel at exposed signal v
/// (fraction of full well): the three channels' range over their level, 3σ_y/(√π·y), with
/// σ_y = sRGB′(v)·√(v·full_well + read_noise²)/full_well (first order in σ_y/y; quantisation
/// leaves the mean range unchanged for σ_y of about an LSB or more).
/// 0 for a noiseless camera. The saturation floor of the calibration curve in dense smoke.
double greyNoiseSaturation(const CameraSensor& sensor, double v);

/// @brief One channel's value through the camera (the per-pixel step of develop).
/// @param signal exposure × radiance: the expected fraction of full well
double developValue(double signal, const CameraSensor& sensor, double white_balance, uint64_t seed, uint64_t pixel,
                    int channel);

}  // namespace smokescan
