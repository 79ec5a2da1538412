#pragma once
/// @file saturation.hpp
/// @brief HSV saturation, the smoke paper's measure of smoke density (its section 3.1): the
/// target's colour saturation falls as smoke veils it.
#include <algorithm>
#include <cmath>
#include <vector>

#include "smokescan/io/image.hpp"

namespace smokescan {

/// HSV saturation (max − min)/max of an RGB triple (any scale); 0 for black.
double hsvSaturation(double r, double g, double b);

/// Statistics of per-pixel saturation over a set of pixels.
struct SaturationStats {
    long long pixels = 0;
    double mean = 0, median = 0, stddev = 0;
};

/// @brief Saturation statistics of the pixels of `display` (sRGB-encoded RGB, as a camera
/// delivers) where mask(x, y) is true. Values are quantised to 8 bits first, as in a video frame.
template <class Mask>
SaturationStats maskedSaturation(const Image& display, Mask&& mask);

SaturationStats saturationStats(std::vector<double> values);

template <class Mask>
SaturationStats maskedSaturation(const Image& display, Mask&& mask)
{
    std::vector<double> v;
    auto q = [](float x) { return double(int(std::lround(std::clamp(x, 0.0f, 1.0f) * 255.0f))); };
    for (int y = 0; y < display.height; ++y)
        for (int x = 0; x < display.width; ++x)
            if (mask(x, y))
                v.push_back(hsvSaturation(q(display.at(x, y, 0)), q(display.at(x, y, 1)), q(display.at(x, y, 2))));
    return saturationStats(std::move(v));
}

}  // namespace smokescan
