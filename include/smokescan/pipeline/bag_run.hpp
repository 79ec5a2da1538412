#pragma once
/// @file bag_run.hpp
/// @brief A scan run recorded as a ROS 2 bag (docs/bags.md) as one library call: what `smokescan
/// scan --bag DIR` writes, without the run's other outputs. The bag's folder is new (or an
/// empty folder) and appears whole or not at all: until the run ends it is a temporary folder
/// beside it (DIR.tmpXXXXXX), taken away on an error, a cancel or a signal.
#include <string>

#include "smokescan/pipeline/laser_run.hpp"
#include "smokescan/pipeline/lidar_run.hpp"

namespace smokescan {

struct BagRunResult {
    long long messages = 0;  ///< scans or frames written
    long long readings = 0;  ///< beams (a 2D laser) or points (a lidar) in them
};

/// @brief A 2D laser's scans on /scan, with /tf_static (and /tf on a robot).
/// @throw Error as LaserRun, or naming dir when it cannot be written; Cancelled by the control.
BagRunResult recordLaserBag(const Scene& scene, const ScanConfig& cfg, const std::string& dir,
                            const RunControl& control = {});

/// @brief A 3D lidar's frames on /points (a planar multi-echo lidar's also on /echoes), with
/// /tf_static (and /tf on a robot). @throw as recordLaserBag, and as LidarRun.
BagRunResult recordLidarBag(const Scene& scene, const LidarRunConfig& cfg, const std::string& dir,
                            const RunControl& control = {});

}  // namespace smokescan
