#include "smokescan/sensor_config/extensions.hpp"

namespace smokescan {

bool ModelExtensions::withinBounds() const
{
    namespace eb = extension_bounds;
    if (!eb::kClockOffset_s.contains(clock_offset_s) || !eb::kThresholdWidth.contains(threshold_width) ||
        !eb::kNoiseGrowth_m.contains(range_noise_growth_m) || !eb::kShare.contains(smoke_obstacle_return) ||
        !eb::kLnFactor.contains(hysteresis))
        return false;
    for (const auto& [name, s] : surfaces)
        if (!eb::kLnFactor.contains(s.threshold_factor) || !eb::kRangeBias.contains(s.range_bias)) return false;
    for (const SectorExtension& s : sectors)
        if (!eb::kSectorAngle_deg.contains(s.from_deg) || !eb::kSectorAngle_deg.contains(s.to_deg) ||
            !(s.to_deg >= s.from_deg) || !eb::kShare.contains(s.dropout))
            return false;
    return true;
}

double ModelExtensions::dropoutAt(double angle_deg) const
{
    double keep = 1;
    for (const SectorExtension& s : sectors)
        if (s.contains(angle_deg)) keep *= 1 - s.dropout;
    return 1 - keep;
}

}  // namespace smokescan
