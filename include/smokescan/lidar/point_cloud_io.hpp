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
#include <cmath>
#include <string>
#include <vector>

#include "smokescan/lidar/lidar_scanner.hpp"

namespace smokescan {

/// @brief Writes the frame's points as a binary PCD file (whole or not at all).
void writePcd(const std::string& path, const LidarFrame& frame);
/// @brief Writes the frame's points as a binary little-endian PLY file (whole or not at all).
void writePly(const std::string& path, const LidarFrame& frame);

/// What a point-cloud file held (readPointCloud).
struct PointCloudFile {
    /// Its points with a finite x, y, z, in the file's order: x, y, z, intensity, ring,
    /// return_index, time and source from the fields of those names (Ouster's `t` in ns as time),
    /// 0 where the file has no such field; range_m from x, y, z; beam = the point's index in the file.
    std::vector<LidarPoint> points;
    std::vector<std::string> fields;  ///< every field's name, in the file's order
    size_t skipped = 0;  ///< points without a finite x, y, z (a driver's "no return")
    size_t skipped_first = 0;  ///< those of them of return index 0 (or without the field)
    double start_s = NAN;  ///< the frame's start time when the header gives it (smokescan's files)
    bool has_viewpoint = false;
    Pose viewpoint;  ///< PCD's VIEWPOINT (PLY: `comment viewpoint`)
};

/// @brief Reads a point-cloud file: PCD v0.7 (DATA ascii or binary) or PLY 1.0 (ascii or binary
/// little endian), told apart by their first line. Fields other than the ones PointCloudFile
/// takes are skipped; x, y and z must be there. At most 8 M points and kPointCloudBytes.
/// @throw Error naming the file (and header line) for a bad header, a truncated body, a field of
/// an unknown type, or an unsupported encoding (PCD's binary_compressed, big-endian PLY).
PointCloudFile readPointCloud(const std::string& path);
/// @brief The same from the file's bytes; `name` names it in errors.
PointCloudFile parsePointCloud(const std::string& bytes, const std::string& name);

/// One field of a binary point record, as a ROS PointCloud2's PointField or a PCD header gives it.
struct PointRecordField {
    std::string name;
    char type = 'F';  ///< F float, U unsigned, I signed
    int size = 4;  ///< bytes of one value: 1, 2, 4 or 8 (F: 4 or 8)
    int count = 1;  ///< values a point
    size_t offset = 0;  ///< bytes from the record's start
};

/// @brief Points from `n` little-endian records, `stride` bytes apart from the first byte of
/// `bytes` (a PointCloud2's data): the fields PointCloudFile takes, as readPointCloud does.
/// @throw Error naming `name` for: more than 2·lidar_limits::kBeamsPerFrame points, a field of
/// another type or outside its record, no x, y or z, fewer bytes than n records.
PointCloudFile readPointRecords(const std::string& bytes, long long n, size_t stride,
                                const std::vector<PointRecordField>& fields, const std::string& name);

/// @brief frames.csv's header line (with its newline): frame, file, start_s, end_s, then the
/// start pose (start_x_m … start_qz) and the end pose (end_x_m … end_qz), quaternions w x y z.
std::string frameIndexHeader();
/// @brief One frame's line of frames.csv (with its newline); `file` is the frame's file name.
std::string frameIndexRow(const LidarFrame& frame, const std::string& file);

}  // namespace smokescan
