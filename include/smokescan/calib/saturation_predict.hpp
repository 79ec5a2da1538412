#pragma once
/// @file saturation_predict.hpp
/// @brief The target saturation a camera would measure, predicted cheaply from the smoke along its
/// line of sight through the calibration curve: the column C = ∫ρ ds from the camera to the target
/// over the distance L is read as the homogeneous density C/L the curve was calibrated with.
/// (Rendering frames and measuring them, SaturationRenderer, is the expensive alternative.)
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "smokescan/calib/saturation_curve.hpp"
#include "smokescan/io/recorded.hpp"
#include "smokescan/media/smoke.hpp"
#include "smokescan/scene/scene.hpp"
#include "smokescan/scene/surfaces.hpp"

namespace smokescan {

/// What the camera measures of the smoke: the mean density along its line of sight to the target.
/// A target made of patches side by side is seen at its centroid (on one of its patches); targets
/// apart (their centroid on none) along the line to the centre of each patch the camera sees (one
/// another surface hides is left out), the lines' densities averaged.
class SaturationPredictor {
public:
    /// @param camera scene camera name ("" = the first)
    /// @param target_prefix surfaces whose names start with it are the target's patches
    /// @throw Error when the scene has no such camera or target, or the camera sees none of the
    /// target's patches' centres.
    SaturationPredictor(const Scene& scene, const SurfaceSet& surfaces, const SaturationCurve& curve,
                        const std::string& camera = "", const std::string& target_prefix = "target_");

    /// Column ∫ρ ds along the lines of sight, their mean [density·m] (regional and local smoke).
    double column(const SmokeField& field) const;
    /// Mean density along the lines of sight, their mean [density]: what the saturation measures.
    double density(const SmokeField& field) const;
    /// Predicted saturation.
    double saturation(const SmokeField& field) const { return curve_(density(field)); }
    /// Camera–target distance, the lines of sight's mean [m].
    double path_m() const;
    /// The lines of sight (one per target patch the camera sees).
    size_t sights() const { return sights_.size(); }

private:
    struct Sight {
        Ray ray;
        double path_m;
        /// The column ∫ρ ds along it [density·m] (regional and local smoke).
        double column(const SmokeField& field) const;
    };
    SaturationCurve curve_;
    std::vector<Sight> sights_;
};

/// | field          | default | unit | meaning                                                  |
/// |----------------|---------|------|----------------------------------------------------------|
/// | from_s, to_s   | –       | s    | scene times of the first and last frame                  |
/// | rate_hz        | 1       | Hz   | frames per second                                        |
/// | sigma          | 0       | –    | standard deviation of the saturation's measurement noise |
/// | clock_offset_s | 0       | s    | camera clock − scene (laser) clock, added to written times |
/// | seed           | 1       | –    | noise seed (frame k's noise depends on seed and k only)  |
struct SaturationSimConfig {
    double from_s = 0, to_s = 0, rate_hz = 1, sigma = 0, clock_offset_s = 0;
    uint64_t seed = 1;
};

/// One camera frame's target saturation, and its patches' where the source knows them.
struct SaturationFrame {
    double saturation = 0;
    std::map<std::string, double> patches;
};
/// Measures frame k at scene time t [s].
using SaturationFrameFn = std::function<SaturationFrame(double time_s, uint64_t frame)>;

/// @brief The camera's stream of a simulated run: `frame` at each frame time, plus noise, clamped
/// to [0, 1], on the camera's clock. Patch columns are those of the first frame.
/// @throw Error for a bad configuration, or a frame without a patch the first one had.
SaturationSeries simulateSaturation(const SaturationFrameFn& frame, const SaturationSimConfig& cfg);

/// @brief simulateSaturation with the predictor's saturation of the scene's smoke at each time.
SaturationSeries simulateSaturation(const Scene& scene, const SaturationPredictor& predictor,
                                    const SaturationSimConfig& cfg);

}  // namespace smokescan
