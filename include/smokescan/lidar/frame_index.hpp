#pragma once
/// @file frame_index.hpp
/// @brief A folder of lidar frames read back: its frames.csv (point_cloud_io.hpp's
/// frameIndexHeader and frameIndexRow), each frame's file, times and poses, checked whole before
/// any frame is read.
#include <cstdint>
#include <string>
#include <vector>

#include "smokescan/core/ray.hpp"

namespace smokescan {

/// One frame's line of frames.csv.
struct FrameIndexEntry {
    uint64_t frame = 0;  ///< the frame's index
    std::string file;  ///< its point-cloud file, a plain name inside the folder
    double start_s = 0, end_s = 0;  ///< scene time of its first and last firing [s]
    Pose start_pose, end_pose;  ///< the sensor's pose in the world then
};

/// @brief Reads DIR/frames.csv: its header as smokescan writes it, then one line a frame (frame,
/// file, start_s, end_s, start pose x y z qw qx qy qz, end pose the same), frames in increasing
/// start time, at most limits::kFrames of them.
/// @param dir the folder (`--points`)
/// @throw Error naming frames.csv and the line: a missing or bad header, a line with the wrong
/// number of fields, a number that is not finite, an end before its start, a start not after the
/// previous frame's, a quaternion whose norm is not 1 (within 1e-3), a file name that is empty or
/// leaves the folder, a file listed twice.
std::vector<FrameIndexEntry> readFrameIndex(const std::string& dir);

/// @brief The same from frames.csv's text; `name` names it in errors.
std::vector<FrameIndexEntry> parseFrameIndex(const std::string& text, const std::string& name);

}  // namespace smokescan
