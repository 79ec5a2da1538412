#pragma once
/// @file point_cloud_io.hpp
/// @brief A lidar frame as a point cloud file, with the fields lidar drivers write: PCD v0.7
/// (binary, as PCL writes it) and PLY 1.0 (binary little endian). Fields, in order:
///
/// | field        | PCD type | PLY type | meaning                                         |
/// |--------------|----------|----------|-------------------------------------------------|
/// | x, y, z      | F 4      | float    | in the sensor's frame at the beam's firing time [m] |
/// | intensity    | F 4      | float    | calibrated reflectivity [%]                     |
/// | ring         | U 2      | uint16   | channel                                         |
/// | return_index | U 1      | uchar    | 0 the mode's first point of the beam, 1 its second |
/// | time         | F 4      | float    | firing time from the frame's start [s]          |
/// | source       | U 1      | uchar    | ground truth: 0 surface, 1 smoke, 2 mirror      |
///
/// The frame's start time is in the header (PCD: its first comment; PLY: `comment start_s`), and
/// its start pose in the world is PCD's VIEWPOINT (tx ty tz qw qx qy qz; PLY: `comment viewpoint`):
/// the cloud placed in the world as a viewer places it, exact for a sensor that stands still
/// during the frame (each point is in the sensor frame of its own firing time). A folder of
/// frames also gets frames.csv (frameIndexHeader, frameIndexRow): each frame's file, start and
/// end time and its start and end pose.
#include <string>

#include "smokescan/lidar/lidar_scanner.hpp"

namespace smokescan {

/// @brief Writes the frame's points as a binary PCD file (whole or not at all).
void writePcd(const std::string& path, const LidarFrame& frame);
/// @brief Writes the frame's points as a binary little-endian PLY file (whole or not at all).
void writePly(const std::string& path, const LidarFrame& frame);

/// @brief frames.csv's header line (with its newline): frame, file, start_s, end_s, then the
/// start pose (start_x_m … start_qz) and the end pose (end_x_m … end_qz), quaternions w x y z.
std::string frameIndexHeader();
/// @brief One frame's line of frames.csv (with its newline); `file` is the frame's file name.
std::string frameIndexRow(const LidarFrame& frame, const std::string& file);

}  // namespace smokescan
