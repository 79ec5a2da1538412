#pragma once
/// @file scan_bag.hpp
/// @brief A 2D laser's run as a ROS 2 bag (docs/bags.md): /scan (sensor_msgs/LaserScan in the
/// sensor's frame, named as its mount), /tf (the robot's pose in "map" at each scan, when the
/// sensor rides on one) and /tf_static (the sensor's mount on its robot, or in "map"); stamps on
/// the scene's clock.
#include <memory>
#include <string>

#include "smokescan/scene/scene.hpp"
#include "smokescan/sensors/scanner.hpp"

namespace smokescan {

class ScanBag {
public:
    /// @param dir the bag's folder: new, or an empty folder (io/atomic_folder.hpp)
    /// @throw Error when dir cannot be made.
    ScanBag(const std::string& dir, const Scene& scene, const Scanner& scanner);
    ~ScanBag();
    /// @brief One scan, in time order. @throw Error for a time before 0 (no ROS stamp).
    void add(const Scan& scan);
    /// @brief Closes the bag's files (staged; nothing is in place until commit).
    void finish();
    /// @brief Moves the folder into place.
    void commit();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace smokescan
