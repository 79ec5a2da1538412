#pragma once
/// @file bag_input.hpp
/// @brief A 2D laser's recorded scans from a ROS 2 bag (docs/bags.md): a rosbag2 folder (its
/// metadata.yaml names its MCAP files) or one .mcap file; the LaserScans of one topic, in the
/// form `fit` and `diagnose` read (io/recorded.hpp); a camera's Images; a 3D lidar's PointCloud2
/// frames.
#include <functional>
#include <string>
#include <vector>

#include "smokescan/bag/ros_messages.hpp"
#include "smokescan/io/image.hpp"
#include "smokescan/io/recorded.hpp"
#include "smokescan/lidar/point_cloud_io.hpp"
#include "smokescan/sensor_config/lrf.hpp"

namespace smokescan {

/// The LaserScans of one topic.
struct BagLaserScans {
    std::string source, topic;  ///< the bag's path; the topic read
    std::vector<LaserScanMsg> scans;  ///< in the bag's order, stamps increasing
    uint64_t beams = 0;  ///< ranges in all the scans (bounded: limits::kBagBeams)
};

/// @brief The files a bag is read from: a folder's metadata.yaml and the files it lists, or the
/// file itself (the run's inputs, which no output may replace).
/// @throw Error naming the bag when one is missing, not a regular file, outside the folder or
/// listed twice, or its storage is not MCAP.
std::vector<std::string> bagInputFiles(const std::string& path);

/// @brief Reads topic `topic` ("" = the bag's only LaserScan topic).
/// @throw Error naming the file for: no such topic (the LaserScan topics are listed), a topic of
/// another type, no messages on it, stamps that do not increase, a storage other than MCAP, or a
/// file that is not valid MCAP (bag/mcap_reader.hpp).
BagLaserScans readBagLaserScans(const std::string& path, const std::string& topic);

/// @brief Calls `each` with every Image on `topic` ("" = the bag's only sensor_msgs/Image topic),
/// in the bag's order, `what` naming the message for errors. A rosbag2 folder, an .mcap file or a
/// ROS 1 .bag file. @return the topic read
/// @throw Error naming the file, as readBagLaserScans, and for stamps that are not times or do
/// not increase.
std::string readBagImages(const std::string& path, const std::string& topic,
                          const std::function<void(ImageMsg&&, const std::string& what)>& each);

/// @brief Calls `each` with every PointCloud2 on `topic` ("" = the bag's only
/// sensor_msgs/PointCloud2 topic), in the bag's order, with its stamp [s] as the frame's start and
/// `what` naming the message for errors (its points: pointCloudFileOf). A rosbag2 folder or an
/// .mcap file. @return the topic read
/// @throw Error naming the file and message, as readBagLaserScans, and for stamps that are not
/// times or do not increase, a ROS 1 bag (not read for point clouds).
std::string readBagPointClouds(
    const std::string& path, const std::string& topic,
    const std::function<void(const PointCloud2Msg&, double start_s, const std::string& what)>& each);

/// @brief A PointCloud2's points as a point-cloud file gives them (lidar/point_cloud_io.hpp: x, y,
/// z, intensity, ring, return, time or Ouster's t, source); `what` names it in errors.
/// @throw Error naming `what` for: a big-endian cloud, a field of an unknown datatype or outside
/// its point, no x, y or z, data shorter than its rows, more than 2·lidar_limits::kBeamsPerFrame
/// points.
PointCloudFile pointCloudFileOf(const PointCloud2Msg& m, const std::string& what);

/// @brief A frame as the camera delivered it: rgb8, bgr8, rgba8 or bgra8 (8-bit sRGB) → RGB in [0, 1].
/// @throw Error naming `what` for another encoding, a zero or over-large size
/// (limits::kFramePixels), or a row step shorter than a row.
Image imageOf(const ImageMsg& m, const std::string& what);

/// @brief Whether `path` is a bag: a folder (rosbag2), or a file starting with MCAP's or a ROS 1
/// bag's magic.
bool isBagPath(const std::string& path);

/// @brief The scans as a laser log of the sensor `spec` describes: times from the stamps, angles
/// from angle_min and angle_increment, ranges in the sensor's unit (snapped to it, as the sensor
/// reported them), REP 117's ±Inf and NaN back to the sensor kind's error codes.
/// @throw Error naming the bag when a scan's beams differ from the first's in count, first angle
/// or step, or from the sensor's (by more than a hundredth of its step).
RecordedLog recordedLogOf(const BagLaserScans& bag, const LrfSpec& spec);

}  // namespace smokescan
