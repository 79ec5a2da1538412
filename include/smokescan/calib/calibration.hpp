#pragma once
/// @file calibration.hpp
/// @brief The density ↔ saturation calibration of the smoke paper (its Fig. 7), from smokescan's
/// own rendered frames: the scene is filled with homogeneous smoke at a sweep of densities, the
/// target's HSV saturation is measured in each frame and the curve is fitted with Ceres.
///
/// | field          | default                            | unit    | meaning                                   |
/// |----------------|------------------------------------|---------|-------------------------------------------|
/// | densities      | 0, 0.0005 … 0.012 (14 values)      | density | the sweep                                 |
/// | field          | TargetRadianceConfig{}             | –       | the converged target radiance: batches of samples on the target's pixels (camera/target_radiance.hpp) |
/// | width, height  | 320, 240                           | px      | frame size                                |
/// | seed           | 1                                  | –       | render seed (frame k uses seed + k)       |
/// | target_prefix  | "target_"                          | –       | surfaces whose names start with it are the target; the rest of the name is the patch |
/// | threshold_saturation | 0.14                         | –       | the paper's Hokuyo threshold              |
/// | path_m         | 2.5                                | m       | laser–target distance for the penetration power |
/// | paper_density  | 0.0028                             | engine density | the paper's density at the threshold |
/// | watch          | null                               | –       | a RenderWatch another thread may stop the sweep with |
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "smokescan/calib/colour_mix_curve.hpp"
#include "smokescan/calib/light_mixing.hpp"
#include "smokescan/calib/saturation_curve.hpp"
#include "smokescan/camera/saturation.hpp"
#include "smokescan/camera/target_radiance.hpp"
#include "smokescan/render/renderer.hpp"
#include "smokescan/scene/scene.hpp"

namespace smokescan {

struct CalibrateConfig {
    std::vector<double> densities = {0.0,    0.0005, 0.001, 0.0015, 0.002, 0.0025, 0.003,
                                     0.0035, 0.004,  0.005, 0.006,  0.008, 0.010,  0.012};
    TargetRadianceConfig field;
    int width = 320, height = 240;
    uint64_t seed = 1;
    std::string camera;
    std::string target_prefix = "target_";
    double threshold_saturation = 0.14;
    double path_m = 2.5;
    double paper_density = 0.0028;
    CurveFitConfig fit;
    /// When set, each frame's render counts its tiles there, and a stop ends the sweep (Error) within
    /// a tile of the frame being rendered.
    RenderWatch* watch = nullptr;
};

struct CalibrationResult {
    /// The colour-mixing curve (colour_mix_curve.hpp) fitted to every patch at once (one
    /// extinction) and to each patch alone; its threshold density. The curve the rest of smokescan
    /// reads (fit, below) is the three-parameter effective curve of the combined points.
    std::vector<PatchPoints> patch_points;
    ColourMixFit mix;
    /// Each patch alone under the joint fit's scattered light (held; `patch_mix_light` says which:
    /// "drifting" or "one colour"), and whether their b's are one extinction.
    PatchExtinctions patch_mix;
    std::string patch_mix_light;
    double mix_threshold_density = 0, mix_threshold_density_se = 0;
    /// The same with a scattered light that drifts from warm to grey as the smoke thickens
    /// (fitColourMix's drifting_light): what describes the points; its threshold density.
    ColourMixFit drift;
    double drift_threshold_density = 0, drift_threshold_density_se = 0;
    /// The light's mixing measured from the patches' colours at each density (light_mixing.hpp),
    /// and the b it gives: independent of the saturation curves (empty without density 0).
    std::vector<LightMixing> mixing;
    double mixing_b = 0, mixing_b_se = 0;
    std::vector<double> floor;  ///< the combined target's noise floor at each density
    std::vector<SaturationPoint> points;  ///< combined target
    std::map<std::string, std::vector<SaturationPoint>> patches;  ///< per colour patch
    CurveFitResult fit;  ///< combined
    std::map<std::string, CurveFitResult> patch_fits;
    double threshold_density = 0, threshold_density_se = 0;  ///< ρ at threshold_saturation
    double penetration_power = 0, penetration_power_se = 0;  ///< ρ* · path_m [density·m]
    double engine_unit_factor = 0;  ///< ρ* / paper_density
    std::vector<int> spp;  ///< samples per target pixel at each density
    std::vector<double> rel_error;  ///< the target radiance's relative error reached at each density
    double seconds = 0;
};

/// @brief The scene with its smoke replaced by one homogeneous box filling the bounds of its
/// surfaces (the room), in the medium of its first regional volume, at `density` throughout.
/// @throw Error for a scene without surfaces.
Scene uniformSmokeScene(const Scene& scene, double density);

/// @brief Renders the sweep and fits. `progress(done, total)` is called after each frame.
/// @throw Error when the scene has no camera or no target surfaces, the fit is degenerate, or the
/// threshold saturation falls outside the sweep (an extrapolation).
CalibrationResult calibrate(const Scene& scene, const CalibrateConfig& cfg,
                            const std::function<void(int, int)>& progress = {});

/// @brief The calibration as JSON text (curve model, parameters, covariance, points, settings),
/// without a final newline.
std::string calibrationJson(const CalibrationResult& r, const CalibrateConfig& cfg, const std::string& scene_source);
/// @brief The calibration as JSON (curve model, parameters, covariance, points, settings), written
/// atomically.
void writeCalibrationJson(const std::string& path, const CalibrationResult& r, const CalibrateConfig& cfg,
                          const std::string& scene_source);

/// @brief The paper's Fig. 7 reproduced: points with error bars, the fitted curve and its 95 %
/// confidence band, the threshold saturation and its density marked. PNG through OpenImageIO.
void writeCalibrationPlot(const std::string& path, const CalibrationResult& r, const CalibrateConfig& cfg);

/// @brief Reads a calibration written by writeCalibrationJson: a file, or the name of a built-in
/// one (calib/*.json compiled in: "bocas"). `patch` "" = the combined target, else that patch's fit.
/// @throw Error naming the file and the missing or bad field.
CurveFitResult readCalibrationJson(const std::string& path_or_name, const std::string& patch = "");

}  // namespace smokescan
