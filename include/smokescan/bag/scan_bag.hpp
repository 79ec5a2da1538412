#pragma once
/// @file scan_bag.hpp
/// @brief A run as a ROS 2 bag (docs/bags.md): a 2D laser's scans (sensor_msgs/LaserScan, /scan),
/// a 3D lidar's frames (sensor_msgs/PointCloud2, /points; a planar one's also as
/// sensor_msgs/MultiEchoLaserScan, /echoes), the omnicam's ranges (LaserScan,
/// /omni/scan) and camera frames (sensor_msgs/Image, /camera/image), each in its sensor's frame
/// named as the sensor; /tf_static holds each sensor's mount (on its robot, or in "map") once, /tf
/// the robot's pose in "map" at each message of a sensor that rides on one. Stamps on the scene's
/// clock (a camera's frames on the camera's own). Topics appear as they are first written.
#include <memory>
#include <string>

#include "smokescan/bag/ros_messages.hpp"
#include "smokescan/io/image.hpp"
#include "smokescan/lidar/lidar_scanner.hpp"
#include "smokescan/scene/scene.hpp"
#include "smokescan/sensors/scanner.hpp"

namespace smokescan {

/// Where a sensor sits: its frame's name, its pose on its robot (or in the world) and its robot.
struct BagFrame {
    std::string name;
    Pose pose;
    int robot = -1;  ///< index into Scene::robots, or −1: fixed in the world
};
/// @brief A laser's or a camera's place in the bag.
BagFrame bagFrameOf(const SensorMount& mount);
BagFrame bagFrameOf(const Camera& camera);

class ScanBag {
public:
    /// @param dir the bag's folder: new, or an empty folder (io/atomic_folder.hpp)
    /// @throw Error when dir cannot be made.
    ScanBag(const std::string& dir, const Scene& scene);
    ~ScanBag();
    /// @brief A 2D laser's scan on /scan, in time order. @throw Error for a time before 0 (no ROS stamp).
    void add(const Scan& scan, const LrfSpec& spec, const SensorMount& mount);
    /// @brief A 3D lidar's frame on /points, in time order.
    void add(const LidarFrame& frame, const SensorMount& mount);
    /// @brief A planar multi-echo lidar's frame on /echoes (sensor_msgs/MultiEchoLaserScan).
    void add(const MultiEchoLaserScanMsg& echoes, const SensorMount& mount);
    /// @brief Any LaserScan on `topic`, stamped with its header's stamp (the scene's clock), from `where`.
    void add(const std::string& topic, const LaserScanMsg& scan, const BagFrame& where);
    /// @brief A camera's delivered frame on /camera/image (rgb8), stamped with the camera's own
    /// clock; the robot's pose (when the camera rides on one) at scene time `scene_time_s`. A
    /// pinhole's frame is NAME_optical_frame (REP 103: +z along the view, +x right, +y down), put
    /// on /tf_static below the camera's own; an omni camera's is its own.
    void addImage(const Image& display, double camera_time_s, double scene_time_s, const Camera& camera);
    /// @brief Closes the bag's files (staged; nothing is in place until commit).
    void finish();
    /// @brief Moves the folder into place.
    void commit();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace smokescan
