#include "smokescan/camera/develop.hpp"

#include <algorithm>
#include <cmath>

#include "smokescan/core/random.hpp"
#include "smokescan/render/renderer.hpp"

namespace smokescan {

double meterExposure(const Image& rad, const CameraSensor& s)
{
    if (s.exposure > 0) return s.exposure;
    double sum = 0;
    for (int y = 0; y < rad.height; ++y)
        for (int x = 0; x < rad.width; ++x)
            sum += 0.2126 * rad.at(x, y, 0) + 0.7152 * rad.at(x, y, 1) + 0.0722 * rad.at(x, y, 2);
    const double mean = sum / std::max(1, rad.width * rad.height);
    return mean > 0 ? s.meter_grey / mean : 1.0;
}

namespace {
/// Poisson(mean) by inversion (small means) or its normal limit (mean ≥ 100, where the two
/// differ by less than the read noise ever matters).
double poisson(double mean, KeyedRng& rng)
{
    if (mean >= 100) return std::max(0.0, mean + std::sqrt(mean) * rng.normal());
    const double u = rng.uniform();
    double p = std::exp(-mean), cdf = p;
    int k = 0;
    while (u > cdf && k < 1000) {
        ++k;
        p *= mean / k;
        cdf += p;
    }
    return k;
}
}  // namespace

double developValue(double signal, const CameraSensor& s, double wb, uint64_t seed, uint64_t pixel, int channel)
{
    double v = std::max(0.0, signal);
    if (s.noise) {
        KeyedRng rng(seed, pixel, uint64_t(channel), 0x43414dULL);
        const double electrons = poisson(std::min(v, 2.0) * s.full_well_e, rng) + s.read_noise_e * rng.normal();
        v = electrons / s.full_well_e;
    }
    v = std::clamp(v, 0.0, 1.0) * wb;  // the full well clips; white balance scales the read-out
    double e = srgbEncode(std::min(v, 1.0));
    if (s.bits > 0) {
        const double levels = double((1 << s.bits) - 1);
        e = std::round(e * levels) / levels;
    }
    return e;
}

double greyNoiseSaturation(const CameraSensor& s, double v)
{
    if (!s.noise || !(v > 0)) return 0.0;
    v = std::min(v, 1.0);
    const double y = srgbEncode(v);
    const double slope = v <= 0.0031308 ? 12.92 : 1.055 / 2.4 * std::pow(v, 1 / 2.4 - 1);
    const double sigma_lin = std::sqrt(v * s.full_well_e + s.read_noise_e * s.read_noise_e) / s.full_well_e;
    // Rounding to the output's levels adds LSB²/12 to a channel's variance but leaves the mean
    // range of three channels unchanged once σ_y is about an LSB or more: not counted.
    const double sigma_y = slope * sigma_lin;
    return 3 * sigma_y / (std::sqrt(M_PI) * y);
}

Image develop(const Image& rad, const CameraSensor& s, double exposure, uint64_t seed)
{
    Image out(rad.width, rad.height, 3);
    for (int y = 0; y < rad.height; ++y)
        for (int x = 0; x < rad.width; ++x) {
            const uint64_t pix = uint64_t(y) * uint64_t(rad.width) + uint64_t(x);
            for (int c = 0; c < 3; ++c)
                out.at(x, y, c) =
                    float(developValue(exposure * rad.at(x, y, c), s, s.white_balance[size_t(c)], seed, pix, c));
        }
    return out;
}

}  // namespace smokescan
