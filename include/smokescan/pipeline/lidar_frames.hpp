#pragma once
/// @file lidar_frames.hpp
/// @brief A 3D lidar's recorded frames (a folder as `smokescan scan --points` writes it:
/// frames.csv and one point cloud per frame, or a ROS 2 bag's PointCloud2 topic) replayed in their scene one at a time and tallied
/// beam by beam (LidarTally): what `smokescan diagnose --points` and `smokescan fit --points` share.
///
/// | field  | default | unit | meaning                                                              |
/// |--------|---------|------|----------------------------------------------------------------------|
/// | scene  | –       | –    | the scene the frames were recorded in (a built-in name or a file)   |
/// | points | –       | –    | the frames' folder, or a ROS 2 bag (rosbag2 folder or .mcap file)    |
/// | topic  | ""      | –    | a bag's PointCloud2 topic ("": its only one)                         |
/// | sensor | vlp16   | –    | the lidar: sensor, returns, rate_hz, columns as LidarRunConfig (its from/to are the frames') |
///
/// The lidar sits on the scene's default lidar mount, as when the frames were simulated. Every
/// point-cloud file must carry the fields `ring` and `time` (the firing time from the frame's
/// start), which say which beam a point is.
#include <functional>
#include <string>

#include "smokescan/diagnose/lidar_diagnosis.hpp"
#include "smokescan/pipeline/lidar_run.hpp"
#include "smokescan/pipeline/run_control.hpp"

namespace smokescan {

struct LidarFramesConfig {
    std::string scene;
    std::string points;
    LidarRunConfig sensor;
    /// Called once the scene is read, before any frame (a caller protects its files).
    std::function<void(const Scene&)> on_scene;
    /// Called once the lidar is set up, before any frame (the caller's own checks).
    std::function<void(const LidarRun&)> on_run;
    bool intensities = false;  ///< the tally keeps each clear beam's intensities (LidarTally::intensities)
    bool keep_points = false;  ///< TalliedFrames::recorded holds every frame's points (to replay them again)
    /// When `points` is a ROS 2 bag (a rosbag2 folder or an .mcap file): its PointCloud2 topic
    /// ("" = its only one). Each message is a frame starting at its stamp (scene time [s]).
    std::string topic;
};

/// @brief Whether `points` names a ROS 2 bag rather than a frames folder: an .mcap file, or a
/// folder with metadata.yaml and without frames.csv.
bool isLidarFramesBag(const std::string& points);

/// The frames tallied, for the caller to read while they live.
struct TalliedFrames {
    const Scene& scene;
    const LidarRun& run;  ///< the replay's lidar
    const LidarTally& tally;
    /// The preset as a written preset's `base` names it: the preset's own base when it extends
    /// one, a file made absolute as the file system resolves it.
    std::string base;
    /// The largest recorded start pose's off the scene's; NaN for a bag's frames, which carry no
    /// pose (the scene's is taken).
    double pose_mismatch_m = 0, pose_mismatch_deg = 0;
    /// Each frame's start time [s] and points, in the listing's order (LidarFramesConfig::keep_points).
    std::vector<std::pair<double, std::vector<LidarPoint>>> recorded;
    /// The bag's topic the frames were read from (the named one or its only PointCloud2 topic);
    /// empty for a frames folder.
    std::string topic;
    /// Frames empty in effect (no point, or first-return points for under a tenth of the beams the
    /// replay is sure of: frames a recorder dropped or cut), left out of the tally (read as every
    /// beam unanswered they would stand for a sensor that fails everywhere at once).
    size_t empty_frames = 0;
};

/// @brief Reads the frames one at a time, replays each and tallies them (the frames kept, those
/// not empty in effect, alternating between folds 0 and 1), then hands the tally to `use`.
/// @param min_frames the fewest frames the caller's work needs (a diagnosis: 2, a fold each)
/// @param control progress after each frame; cancel asked before each
/// @throw Error naming the folder, file or option at fault: too few frames, a frame without ring
/// or time, frames whose points mostly match no beam of the sensor, a preset path lidar.toml
/// cannot name, the return mode the points do not hold.
void tallyLidarFrames(const LidarFramesConfig& cfg, size_t min_frames, const RunControl& control,
                      const std::function<void(const TalliedFrames&)>& use);

}  // namespace smokescan
