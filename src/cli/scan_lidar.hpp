#pragma once
// `smokescan scan --sensor PRESET`: frames of a 3D lidar (lidar/lidar_scanner.hpp) as point clouds.
#include <cstdint>
#include <string>

namespace smokescan {
struct Scene;
}

namespace smokescan::cli {

struct LidarScanArgs {
    std::string scene, sensor, returns = "strongest", points_dir, format = "pcd", bag;
    std::string range_image, top_view;  ///< pictures of the first frame (PNG)
    double top_view_m = 10;  ///< the top view's half width [m]
    double rate_hz = 0;  ///< 0: the preset's
    int columns = 0;  ///< 0: the preset's
    double from = 0, to = 0;  ///< NaN: the scene's start, its start (one frame)
    uint64_t seed = 1;
    bool returns_given = false;  ///< --returns on the command line
};

/// @brief Runs a lidar scan of `scene` (loaded from a.scene): one point cloud per frame in a new
/// folder, named by frame index.
int runLidarScan(const Scene& scene, const LidarScanArgs& a);

}  // namespace smokescan::cli
