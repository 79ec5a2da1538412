#pragma once
/// @file scan_messages.hpp
/// @brief smokescan's scans and poses as ROS messages (docs/bags.md): a 2D laser's scan as a
/// LaserScan in the sensor's frame, a pose as a transform.
#include <string>

#include "smokescan/bag/ros_messages.hpp"
#include "smokescan/core/ray.hpp"
#include "smokescan/sensors/scanner.hpp"

namespace smokescan {

/// @brief A 2D laser's scan as a LaserScan: beams from the spec's first angle (the sensor's own
/// convention, as its log), ranges in metres, error values as its kind's REP 117 meaning
/// (LaserKind::rep117), no intensities (the 2D lasers report none).
/// @param frame_id the sensor's frame (its mount's name)
LaserScanMsg laserScanOf(const Scan& scan, const LrfSpec& spec, const std::string& frame_id);

/// @brief `child`'s pose in `parent` at `stamp`.
TransformStampedMsg transformOf(const Pose& pose, const RosTime& stamp, const std::string& parent,
                                const std::string& child);

}  // namespace smokescan
