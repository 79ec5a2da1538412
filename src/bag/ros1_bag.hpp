#pragma once
// Internal: ROS 1 bags (format 2.0), read by Debian's librosbag_storage (bag/bag_input.hpp
// dispatches to it for a file starting with "#ROSBAG V2.0").
#include <functional>
#include <string>

#include "ros1_structure.hpp"
#include "smokescan/bag/bag_input.hpp"

namespace smokescan::detail {

/// @brief Appends a scan after the checks every source's scans pass (bag_input.cpp): a stamp
/// that is a time after the previous scan's, the run's beams within limits::kBagBeams.
/// @throw Error naming `what`.
void addLaserScan(BagLaserScans& out, LaserScanMsg&& scan, const std::string& what);

/// @brief The LaserScans on `topic` ("" = the only sensor_msgs/LaserScan topic) of a ROS 1 bag.
/// Its record structure is checked first (every length within the file, chunk sizes and counts
/// bounded, a known compression), so that librosbag only sees a well-formed file.
/// @throw Error naming the file.
BagLaserScans readRos1LaserScans(const std::string& path, const std::string& topic);

/// @brief Calls `each` with every sensor_msgs/Image on `topic` ("" = the only Image topic) of a
/// ROS 1 bag, checked as readRos1LaserScans checks scans. @return the topic read
/// @throw Error naming the file.
std::string readRos1Images(const std::string& path, const std::string& topic,
                           const std::function<void(ImageMsg&&, const std::string& what)>& each);

/// @brief Calls `each` with every sensor_msgs/PointCloud2 on `topic` ("" = the only PointCloud2
/// topic) of a ROS 1 bag, checked as readRos1LaserScans checks scans and its layout as a ROS 2
/// bag's (checkPointCloud2Layout). @return the topic read
/// @throw Error naming the file.
std::string readRos1PointClouds(const std::string& path, const std::string& topic,
                                const std::function<void(PointCloud2Msg&&, const std::string& what)>& each);

}  // namespace smokescan::detail
