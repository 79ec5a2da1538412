#pragma once
/// @file lidar_diagnose_run.hpp
/// @brief `smokescan diagnose --points DIR` as one library call: a 3D lidar's recorded frames (a
/// folder as `smokescan scan --points` writes it: frames.csv and one point cloud per frame) replayed
/// in their scene frame by frame and diagnosed (diagnose/lidar_diagnosis.hpp).
///
/// | field  | default | unit | meaning                                                              |
/// |--------|---------|------|----------------------------------------------------------------------|
/// | scene  | –       | –    | the scene the frames were recorded in (a built-in name or a file)   |
/// | points | –       | –    | the frames' folder                                                   |
/// | sensor | vlp16   | –    | the lidar: sensor, returns, rate_hz, columns as LidarRunConfig (its from/to are the frames') |
/// | diag   | –       | –    | LidarDiagnosisConfig                                                |
///
/// The lidar sits on the scene's default lidar mount, as when the frames were simulated. Every
/// point-cloud file must carry the fields `ring` and `time` (the firing time from the frame's
/// start), which say which beam a point is.
#include <functional>
#include <string>

#include "smokescan/diagnose/lidar_diagnosis.hpp"
#include "smokescan/io/atomic_folder.hpp"
#include "smokescan/pipeline/lidar_run.hpp"
#include "smokescan/pipeline/run_control.hpp"

namespace smokescan {

struct LidarDiagnoseRunConfig {
    std::string scene;
    std::string points;
    LidarRunConfig sensor;
    LidarDiagnosisConfig diag;
    /// Called once the scene is read, before any frame (a caller protects its files).
    std::function<void(const Scene&)> on_scene;
    std::string topic;  ///< when `points` is a ROS 2 bag: its PointCloud2 topic ("" = its only one)
};

struct LidarDiagnoseRunResult {
    LidarDiagnosis diagnosis;
    std::string sensor;  ///< the lidar's name
};

/// @brief The diagnosed preset extended by the diagnosis's named findings, as a preset file's
/// text: `base` the preset diagnosed (its own base when it extends one), its extensions kept, and
/// a dropping channel's excess missed share over the others' (as the dropout that gives it:
/// excess / (1 − the others' share)) as the ring's dropout, a window sector's as the
/// sector's, a biased channel's bias added to the ring's range offset. A surface's threshold and
/// smoke taken as first returns are not extensions yet: named in a comment.
/// @param base the preset as given (`--sensor`: a built-in name, or a file made absolute)
std::string extendedLidarPreset(const LidarDiagnosis& d, const LidarSpec& diagnosed, const std::string& base);

/// @brief Reads the frames one at a time, replays each and diagnoses them.
/// @param control progress after each frame; cancel asked before each
/// @throw Error naming the folder, file or option at fault: fewer than two frames, a frame
/// without ring or time, frames whose points mostly match no beam of the sensor.
LidarDiagnoseRunResult runLidarDiagnosis(const LidarDiagnoseRunConfig& cfg, const RunControl& control = {});

/// @brief Writes diagnosis.json, report.md and lidar.toml (the extended preset) into `out` and commits it.
void writeLidarDiagnosisFolder(AtomicFolder& out, const LidarDiagnoseRunResult& r);

}  // namespace smokescan
