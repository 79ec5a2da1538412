#include "smokescan/sensor_config/physical_params.hpp"

#include <algorithm>

#include "smokescan/sensor_config/laser_kind.hpp"

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

PhysicalParams physicalDefaults(SensorType type) { return laserKind(type).physicalDefaults(); }

}  // namespace smokescan
