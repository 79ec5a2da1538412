#pragma once
/// @file bag_saturation.hpp
/// @brief The smoke paper's saturation series measured on a recorded bag's camera frames
/// (sensor_msgs/Image, docs/bags.md): each frame's target saturation over pixel polygons
/// (camera/frame_saturation.hpp), on the frames' header stamps (the camera's clock).
#include <functional>
#include <string>

#include "smokescan/camera/frame_saturation.hpp"
#include "smokescan/io/recorded.hpp"

namespace smokescan {

/// @param path a rosbag2 folder or .mcap file
/// @param topic its Image topic ("" = the only one)
/// @param regions the target's patches (polygons: a bag holds no id frames)
/// @throw Error naming the bag and message: a missing topic or one of another type, no frames, an
/// encoding without colour, stamps that do not increase, a region without pixels in a frame.
/// @param each called after each frame with the frames measured so far (on the calling thread)
SaturationSeries measureBagSaturation(const std::string& path, const std::string& topic, const FrameRegions& regions,
                                      const std::function<void(long long)>& each = {});

}  // namespace smokescan
