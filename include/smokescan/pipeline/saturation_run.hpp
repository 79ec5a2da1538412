#pragma once
/// @file saturation_run.hpp
/// @brief `smokescan saturation` as one library call: a target's HSV saturation measured on a
/// run of camera frames (image files or folders, or a bag's Image topic), as the smoke paper
/// measured its smoke (docs/calibration.md).
///
/// | field       | default   | meaning                                                              |
/// |-------------|-----------|----------------------------------------------------------------------|
/// | inputs      | {}        | image files or folders of frames (sorted by name), or              |
/// | bag, topic  | "", ""    | a bag whose sensor_msgs/Image topic ("" = its only one) holds them   |
/// | rects       | {}        | patches "NAME=x,y,width,height" [px]                                 |
/// | polygons    | {}        | patches "NAME=x1,y1,x2,y2,x3,y3,…" [px]                              |
/// | ids, scene  | "", ""    | or the target found by id: `render --ids` images and the scene they name |
/// | target_prefix | "target_" | with ids: the surfaces of the target                               |
/// | timestamps  | ""        | files' times: lines "file,time_s" or one time per frame in name order |
/// | fps         | 0         | or the number in a file's name is a frame index at this rate (0: a time [s]) |
/// | on_scene    | none      | called with the scene once it is read, before any frame (a caller protecting its files) |
#include <functional>
#include <string>
#include <vector>

#include "smokescan/io/recorded.hpp"
#include "smokescan/pipeline/run_control.hpp"
#include "smokescan/scene/scene.hpp"

namespace smokescan {

struct SaturationRunConfig {
    std::vector<std::string> inputs;
    std::string bag, topic;
    std::vector<std::string> rects, polygons;
    std::string ids, scene, target_prefix = "target_", timestamps;
    double fps = 0;
    std::function<void(const Scene&)> on_scene;
};

/// @brief Measures the frames. @param control progress after each frame (files), cancel before each
/// @throw Error naming the option or file at fault; Cancelled
SaturationSeries runSaturation(const SaturationRunConfig& cfg, const RunControl& control = {});

}  // namespace smokescan
