#include "smokescan/omni/omni_scan_message.hpp"

#include <cmath>
#include <limits>

namespace smokescan {

LaserScanMsg omniLaserScanOf(const OmniRangeResult& r, const OmniRangeConfig& cfg, double time_s, double period_s,
                             const std::string& frame_id)
{
    LaserScanMsg m;
    m.header.stamp = RosTime::fromSeconds(time_s);
    m.header.frame_id = frame_id;
    const double n = double(r.range_m.size());
    m.angle_min = 0;
    m.angle_increment = float(2 * M_PI / n);
    m.angle_max = float(2 * M_PI * (n - 1) / n);
    m.time_increment = 0;  // one frame: every scanline at once
    m.scan_time = float(period_s);
    m.range_min = float(cfg.min_range_m);
    m.range_max = float(cfg.max_range_m);
    constexpr float kInf = std::numeric_limits<float>::infinity();
    m.ranges.reserve(r.range_m.size());
    for (size_t s = 0; s < r.range_m.size(); ++s)
        m.ranges.push_back(r.status[s] == OmniRangeStatus::MaxRange       ? kInf
                               : r.status[s] == OmniRangeStatus::MinRange ? -kInf
                                                                          : float(r.range_m[s]));
    return m;
}

}  // namespace smokescan
