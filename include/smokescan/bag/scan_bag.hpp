#pragma once
/// @file scan_bag.hpp
/// @brief A sensor's run as a ROS 2 bag (docs/bags.md): a 2D laser's scans on /scan
/// (sensor_msgs/LaserScan) or a 3D lidar's frames on /points (sensor_msgs/PointCloud2), in the
/// sensor's frame named as its mount; /tf (the robot's pose in "map" at each scan or frame's
/// start, when the sensor rides on one), /camera/image (rendered frames, when asked) and /tf_static (the sensor's mount on its robot, or in
/// "map"); stamps on the scene's clock.
#include <memory>
#include <string>

#include "smokescan/io/image.hpp"
#include "smokescan/lidar/lidar_scanner.hpp"
#include "smokescan/scene/scene.hpp"
#include "smokescan/sensors/scanner.hpp"

namespace smokescan {

class ScanBag {
public:
    /// @param dir the bag's folder: new, or an empty folder (io/atomic_folder.hpp)
    /// @throw Error when dir cannot be made.
    /// @param mount the sensor: its name is its frame, its pose and robot the transforms
    /// @param lidar whether it is a 3D lidar (/points) or a 2D laser (/scan)
    ScanBag(const std::string& dir, const Scene& scene, const SensorMount& mount, bool lidar);
    ~ScanBag();
    /// @brief A 2D laser's scan, in time order. @throw Error for a time before 0 (no ROS stamp).
    void add(const Scan& scan, const LrfSpec& spec);
    /// @brief A 3D lidar's frame, in time order.
    void add(const LidarFrame& frame);
    /// @brief A camera's delivered frame on /camera/image (sensor_msgs/Image, rgb8), stamped with
    /// the camera's own clock, `camera` its frame.
    void addImage(const Image& display, double camera_time_s, const std::string& camera);
    /// @brief Closes the bag's files (staged; nothing is in place until commit).
    void finish();
    /// @brief Moves the folder into place.
    void commit();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace smokescan
