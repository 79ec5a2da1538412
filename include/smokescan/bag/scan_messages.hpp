#pragma once
/// @file scan_messages.hpp
/// @brief smokescan's scans and poses as ROS messages (docs/bags.md): a 2D laser's scan as a
/// LaserScan in the sensor's frame, a pose as a transform.
#include <optional>
#include <string>
#include <vector>

#include "smokescan/bag/ros_messages.hpp"
#include "smokescan/core/ray.hpp"
#include "smokescan/io/image.hpp"
#include "smokescan/lidar/lidar_scanner.hpp"
#include "smokescan/lidar/lidar_spec.hpp"
#include "smokescan/sensors/scanner.hpp"

namespace smokescan {

/// @brief A 2D laser's scan as a LaserScan: beams from the spec's first angle (the sensor's own
/// convention, as its log), ranges in metres, error values as its kind's REP 117 meaning
/// (LaserKind::rep117), no intensities (the 2D lasers report none).
/// @param frame_id the sensor's frame (its mount's name)
LaserScanMsg laserScanOf(const Scan& scan, const LrfSpec& spec, const std::string& frame_id);

/// @brief A 3D lidar's frame as a PointCloud2 (height 1, little-endian, dense), stamped at the
/// frame's first firing, with the fields the drivers write: x, y, z, intensity (float32: metres in
/// the sensor's frame at each beam's firing, the calibrated reflectivity in %), ring (uint16),
/// return (uint8: 0 the mode's first point of a beam, 1 its second), source (uint8: 0 surface,
/// 1 smoke, 2 mirror: ground truth drivers do not have), time (float32: seconds from the frame's
/// start, as Velodyne's driver writes it); 24 bytes a point.
PointCloud2Msg pointCloudOf(const LidarFrame& frame, const std::string& frame_id);

/// A lidar pattern that is a 2D scan: one ring in the sensor's x–y plane, its azimuths evenly spaced.
struct PlanarFan {
    double angle_min_rad = 0, step_rad = 0;  ///< the first beam's azimuth; the next's minus it
    double time_step_s = 0;  ///< between beams' firings
};
/// @brief The fan a pattern is, or nothing: at least two beams, every one at elevation 0 on
/// channel 0, beam i at angle_min + i·step (to a hundredth of the step) and fired at
/// t0 + i·time_step (to a tenth of it: a pattern file's times rounded to µs).
std::optional<PlanarFan> planarFan(const std::vector<PatternBeam>& pattern);

/// @brief A planar lidar's frame as a MultiEchoLaserScan: beam i's echoes are its points, the
/// return mode's (one, or two with dual), nearest first (range along the beam [m], intensity the
/// calibrated reflectivity [%]); a beam without an echo has none. Stamped at the frame's start. @param spec the sensor (range limits, rate)
MultiEchoLaserScanMsg multiEchoOf(const LidarFrame& frame, const PlanarFan& fan, size_t beams, const LidarSpec& spec,
                                  const std::string& frame_id);

/// @brief A delivered camera frame (values in [0, 1], 8-bit sRGB as the camera gives them) as an
/// rgb8 Image stamped `stamp`.
ImageMsg imageOf(const Image& display, const RosTime& stamp, const std::string& frame_id);

/// @brief `child`'s pose in `parent` at `stamp`.
TransformStampedMsg transformOf(const Pose& pose, const RosTime& stamp, const std::string& parent,
                                const std::string& child);

}  // namespace smokescan
