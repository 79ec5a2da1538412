#include "smokescan/sensor_config/physical_params.hpp"

#include <algorithm>

namespace smokescan {
namespace {

double smoothstep(double x)
{
    x = std::clamp(x, 0.0, 1.0);
    return x * x * (3 - 2 * x);
}

}  // namespace

double PhysicalParams::overlapSettled_m() const
{
    return std::max({window_m, overlap_start_m, overlap_full_m, overlap_blur_m > 0 ? overlap_blur_m : overlap_start_m});
}

double PhysicalParams::overlap(double r) const
{
    if (r < window_m) return 0.0;  // inside the housing
    const double s = overlap_full_m <= overlap_start_m
        ? (r >= overlap_full_m ? 1.0 : 0.0)
        : smoothstep((r - overlap_start_m) / (overlap_full_m - overlap_start_m));
    // Below the biaxial overlap only defocused light reaches the detector: a small floor that
    // itself falls as r² nearer than overlap_blur_m (a blur circle larger than the detector).
    const double blur = overlap_blur_m > 0 ? overlap_blur_m : overlap_start_m;
    const double x = r / std::max(blur, 1e-9);
    return std::max(s, overlap_floor * std::min(1.0, x * x));
}

PhysicalParams physicalDefaults(SensorType type)
{
    PhysicalParams p;
    switch (type) {
    case SensorType::Urg04lx:
        p.overlap_start_m = 1.5;
        p.overlap_full_m = 3.0;
        p.overlap_floor = 0.03;
        // Calibrated, both (docs/sensors.md): the amplitude threshold snr_min·noise_floor puts the
        // bocas blue paper's onset at the paper's 0.007 density·m; the noise alone sets how sharp
        // the onset is, and the paper saw no errors below it (5.4e-4 with snr_min 8 gave two-wave
        // errors from 0.004 density·m, in the first puff).
        p.snr_min = 25;
        p.noise_floor = 1.728e-4;
        break;
    case SensorType::Lms200:
        p.divergence_mrad = 12.0;
        p.noise_floor = 5e-5;  // calibrated: dense plume cores read as obstacles, thin edges as 8189 (docs/sensors.md)
        break;
    }
    return p;
}

}  // namespace smokescan
