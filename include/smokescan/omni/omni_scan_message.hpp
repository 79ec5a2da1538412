#pragma once
/// @file omni_scan_message.hpp
/// @brief The omnicam's ranges as a ROS LaserScan (docs/bags.md), in the camera's frame: scanline
/// s at azimuth 2π·s/N from the camera's local +x towards +y (angle_min 0, angle_increment 2π/N),
/// floor distances [m]; a scanline that found no obstacle within the maximum range reads +Inf and
/// one whose obstacle lies nearer than the minimum reads −Inf (REP 117; the text log writes the
/// range limits themselves), range_min and range_max the rangefinder's.
#include <string>

#include "smokescan/bag/ros_messages.hpp"
#include "smokescan/omni/omni_rangefinder.hpp"

namespace smokescan {

/// @param time_s the frame's time on the scene's clock [s]
/// @param period_s the time between frames [s] (scan_time)
/// @param frame_id the camera's name
LaserScanMsg omniLaserScanOf(const OmniRangeResult& r, const OmniRangeConfig& cfg, double time_s, double period_s,
                             const std::string& frame_id);

}  // namespace smokescan
