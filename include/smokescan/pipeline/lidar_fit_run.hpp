#pragma once
/// @file lidar_fit_run.hpp
/// @brief `smokescan fit --points DIR` as one library call: a 3D lidar's recorded frames replayed
/// in their scene (pipeline/lidar_frames.hpp) and each surface's reflectance factor fitted from
/// the recorded intensities (fit/lidar_fit.hpp); the preset extended by the factors.
///
/// The fit's model of the peak at factor k is exact at k = 1 (the replay's own) and at its nodes
/// ½ and ¼, a parabola between: a factor away from them reads up to 1 % off (0.807 for 0.8). So
/// the frames are replayed again with the factors found, and fitted again against that replay
/// (factors near 1, where the model is exact), until every surface's step is within a tenth of
/// its statistical error or max_replays replays are done; the factors are the steps' product.
///
/// | field  | default | unit | meaning                                              |
/// |--------|---------|------|------------------------------------------------------|
/// | frames | –       | –    | LidarFramesConfig: the scene, the frames' folder, the lidar |
/// | fit    | –       | –    | LidarFitConfig                                       |
#include <string>
#include <vector>

#include "smokescan/fit/lidar_fit.hpp"
#include "smokescan/pipeline/lidar_frames.hpp"

namespace smokescan {

struct LidarFitRunConfig {
    LidarFramesConfig frames;
    LidarFitConfig fit;
    int max_replays = 5;  ///< the frames' replays at most (1: the preset's alone)
};

struct LidarFitRunResult {
    LidarFitResult fit;
    std::vector<std::string> surface_names;  ///< the scene's surfaces (SurfaceReflectanceFit::surface)
    std::string sensor, returns, scene;  ///< what was fitted, for reports
    std::string points, topic;  ///< the frames read: a folder or a bag, and the bag's topic ("" for a folder)
    size_t frames = 0;
    int replays = 1;  ///< the frames replayed this many times (the last with the factors before the last step)
    long long clear = 0;  ///< clear beams answered at their surface (the fit's candidates)
    long long unusable_intensities =
        0;  ///< of those answered, recorded intensities not finite or not positive: left out
    double range_sd_m = NAN;  ///< the clear beams' range residuals' robust sd (1.4826·MAD) [m]
    double range_sd_se_m = NAN;  ///< its standard error (1.166·sd/√n, the MAD's for a normal)
    double preset_range_sd_m = NAN;  ///< the preset's range_sigma_m
    double pose_mismatch_m = 0, pose_mismatch_deg = 0;  ///< as TalliedFrames's (NaN for a bag's frames)
    size_t empty_frames = 0;  ///< frames empty in effect, left out (TalliedFrames's)
    std::string preset;  ///< lidar.toml's text: the preset extended by the fitted factors
    std::vector<int> at_bound;  ///< surfaces whose written factor was held at 0.01 or 10
};

/// @brief The preset `fitted` extended by each fitted surface's reflectance factor (times the
/// factor it had, held within 0.01–10), as a preset file's text whose `base` is `base`
/// (TalliedFrames::base). A surface whose name a preset cannot hold is named in a comment only.
/// @param at_bound receives the surfaces whose written factor was held at a bound (may be null)
std::string fittedLidarPreset(const LidarFitResult& fit, const std::vector<std::string>& surface_names,
                              const LidarSpec& fitted, const std::string& base, std::vector<int>* at_bound = nullptr);

/// @brief Reads the frames one at a time, replays each, fits the factors.
/// @throw Error as tallyLidarFrames, or when no surface has enough usable beams.
LidarFitRunResult runLidarFit(const LidarFitRunConfig& cfg, const RunControl& control = {});

/// @brief The fit as JSON text (the report of `smokescan fit --points`).
std::string lidarFitJson(const LidarFitRunResult& r);

}  // namespace smokescan
