#pragma once
/// @file frame_pictures.hpp
/// @brief A lidar frame as pictures: its range image (channels × columns) and its points seen from
/// above, each coloured by what returned the echo (a surface: grey; smoke: orange).
#include "smokescan/io/image.hpp"
#include "smokescan/lidar/lidar_scanner.hpp"

namespace smokescan {

/// @brief The range image of a spinning lidar's frame: a row per channel, highest elevation on
/// top, a column per firing column placed by each beam's own azimuth (destaggered), straight
/// ahead in the middle; shade = the first kept echo's range (white near, dark at range_max_m),
/// orange where smoke sent it, black where no echo came back. Rows are repeated so that the
/// picture is about a quarter as high as it is wide. range_max_m ≤ 0: the frame's 99th percentile.
/// @throw Error for a lidar without channels × columns (a pattern file's).
Image rangeImage(const LidarFrame& frame, const LidarSpec& spec, double range_max_m);

/// @brief The frame's points seen from above in the sensor's frame (x to the right, y up),
/// `size_px` square over ±half_width_m: surface echoes dark grey, smoke echoes orange, the sensor
/// a red mark.
Image topView(const LidarFrame& frame, double half_width_m, int size_px);

}  // namespace smokescan
