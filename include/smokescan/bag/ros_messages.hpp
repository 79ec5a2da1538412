#pragma once
/// @file ros_messages.hpp
/// @brief The ROS 2 messages smokescan writes and reads, as plain structs: each with its type
/// name, its definition as ROS 2 records it in a bag (ros2msg: the .msg text, then each type it
/// uses after a line of 80 '=' and "MSG: pkg/Type"), and its CDR form (bag/cdr.hpp).
///
/// | message                      | what smokescan puts in it                                     |
/// |------------------------------|---------------------------------------------------------------|
/// | sensor_msgs/msg/LaserScan    | a 2D laser's scan; error values as REP 117 (docs/bags.md)     |
/// | tf2_msgs/msg/TFMessage       | the robot's pose over time (/tf), each sensor's mount (/tf_static) |
/// | sensor_msgs/msg/PointCloud2  | a 3D lidar's frame with its drivers' fields                   |
/// | sensor_msgs/msg/Image        | a rendered camera frame, rgb8 (8-bit sRGB as delivered)       |
/// | sensor_msgs/msg/MultiEchoLaserScan | a planar multi-echo lidar's frame, each beam's echoes |
#include <cstdint>
#include <string>
#include <vector>

namespace smokescan {

/// builtin_interfaces/msg/Time.
struct RosTime {
    int32_t sec = 0;
    uint32_t nanosec = 0;
    /// @brief From seconds on the scene's clock, rounded to the nanosecond.
    /// @throw Error for a negative or non-finite time, or one past 2^31 s.
    static RosTime fromSeconds(double t_s);
    uint64_t nanoseconds() const { return uint64_t(sec) * 1000000000ULL + nanosec; }
};

/// std_msgs/msg/Header.
struct RosHeader {
    RosTime stamp;
    std::string frame_id;
};

/// sensor_msgs/msg/LaserScan.
struct LaserScanMsg {
    RosHeader header;
    float angle_min = 0, angle_max = 0, angle_increment = 0;  ///< [rad]
    float time_increment = 0, scan_time = 0;  ///< [s]
    float range_min = 0, range_max = 0;  ///< [m]
    std::vector<float> ranges;  ///< [m]; −Inf too close, +Inf no return, NaN a measurement error
    std::vector<float> intensities;
};

/// sensor_msgs/msg/MultiEchoLaserScan: LaserScan's fields, each beam's echoes (LaserEcho).
struct MultiEchoLaserScanMsg {
    RosHeader header;
    float angle_min = 0, angle_max = 0, angle_increment = 0;  ///< [rad]
    float time_increment = 0, scan_time = 0;  ///< [s]
    float range_min = 0, range_max = 0;  ///< [m]
    std::vector<std::vector<float>> ranges;  ///< per beam, its echoes' ranges [m] (none: no echo)
    std::vector<std::vector<float>> intensities;  ///< per beam, its echoes' intensities
};

/// geometry_msgs/msg/TransformStamped: child_frame_id's pose in header.frame_id.
struct TransformStampedMsg {
    RosHeader header;
    std::string child_frame_id;
    double translation[3] = {0, 0, 0};  ///< [m]
    double rotation[4] = {0, 0, 0, 1};  ///< quaternion x, y, z, w
};

/// tf2_msgs/msg/TFMessage.
struct TfMsg {
    std::vector<TransformStampedMsg> transforms;
};

/// sensor_msgs/msg/PointField.
struct PointFieldMsg {
    std::string name;
    uint32_t offset = 0;
    uint8_t datatype = 0;  ///< 1 INT8 … 7 FLOAT32, 8 FLOAT64
    uint32_t count = 1;
};

/// sensor_msgs/msg/PointCloud2.
struct PointCloud2Msg {
    RosHeader header;
    uint32_t height = 1, width = 0;
    std::vector<PointFieldMsg> fields;
    bool is_bigendian = false;
    uint32_t point_step = 0, row_step = 0;
    std::vector<uint8_t> data;
    bool is_dense = true;
};

/// sensor_msgs/msg/Image.
struct ImageMsg {
    RosHeader header;
    uint32_t height = 0, width = 0;
    std::string encoding;  ///< e.g. "rgb8"
    uint8_t is_bigendian = 0;
    uint32_t step = 0;  ///< bytes a row
    std::vector<uint8_t> data;
};

/// A message type as a bag records it.
struct RosType {
    const char* name;  ///< e.g. "sensor_msgs/msg/LaserScan"
    const char* definition;  ///< ros2msg text with its dependencies
};
extern const RosType kLaserScanType, kTfType, kPointCloud2Type, kImageType, kMultiEchoLaserScanType;

/// @brief CDR bytes of a message.
std::vector<uint8_t> encode(const LaserScanMsg& m);
std::vector<uint8_t> encode(const TfMsg& m);
std::vector<uint8_t> encode(const PointCloud2Msg& m);
std::vector<uint8_t> encode(const ImageMsg& m);
std::vector<uint8_t> encode(const MultiEchoLaserScanMsg& m);
/// @brief A message from its CDR bytes. @param what names it in errors.
/// @throw Error naming `what` for bytes that are not such a message.
LaserScanMsg decodeLaserScan(const std::vector<uint8_t>& b, const std::string& what);
TfMsg decodeTf(const std::vector<uint8_t>& b, const std::string& what);
PointCloud2Msg decodePointCloud2(const std::vector<uint8_t>& b, const std::string& what);
/// @brief Refuses a PointCloud2 whose rows hold more points than their bytes (width × point_step
/// over row_step) or whose bytes are not its rows' (height × row_step): what every reader checks.
/// @throw Error naming `what`.
void checkPointCloud2Layout(const PointCloud2Msg& m, const std::string& what);
ImageMsg decodeImage(const std::vector<uint8_t>& b, const std::string& what);

}  // namespace smokescan
