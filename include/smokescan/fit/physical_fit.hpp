#pragma once
/// @file physical_fit.hpp
/// @brief From recorded data back to the physical model: the URG-04LX receiver noise floor fitted
/// to a surface's error counts, so `smokescan fit --model physical` writes a physical sensor file
/// (docs/fitting.md, "Physical model").
///
/// The physical model's error probability is not a probit: the two waves' amplitude test (code 8)
/// gives a long tail before the low-intensity cut-off (code 1). So the noise floor is not read off
/// the probit's S*; it is fitted by maximum likelihood to the aligned scans with the model's own
/// probability. Per scan k, the saturation gives the density ρ_k through the calibration curve;
/// the scene's regional smoke, scaled to ρ_k, gives each beam's noise-free amplitudes (tabulated
/// over ρ once); amcwErrorProbability turns them into p_k(σ). The e_k errors of n_k beams are
/// binomial; the fit is maximum likelihood in θ = ln σ (Levenberg–Marquardt on signed deviance
/// residuals, with Ceres), the covariance from the Fisher information at the solution, made
/// cluster-robust over blocks of block_s, plus the calibration curve's error (the fit repeated
/// with the densities moved by the curve's standard error at S*). The clock offset is the
/// threshold fit's, held.
///
/// | field        | default | unit | meaning                                                 |
/// |--------------|---------|------|---------------------------------------------------------|
/// | grid         | 161     | –    | densities tabulated between 0 and the largest observed   |
/// | time_step_s  | 1       | s    | scene times searched for the densest smoke state (its shape is kept) |
/// | block_s      | 2       | s    | scans within a block share saturation noise (robust covariance) |
/// | iterations   | 50      | –    | Levenberg–Marquardt iterations at most                   |
#include <string>

#include "smokescan/calib/saturation_curve.hpp"
#include "smokescan/fit/beam_groups.hpp"
#include "smokescan/fit/sensor_fit.hpp"
#include "smokescan/scene/scene.hpp"
#include "smokescan/scene/surfaces.hpp"

namespace smokescan {

struct UrgNoiseFloorConfig {
    int grid = 161;
    double time_step_s = 1.0;
    double block_s = 2.0;
    int iterations = 50;
};

struct UrgNoiseFloorResult {
    bool ok = false;
    std::string diagnosis;  ///< why not ("" when ok)
    std::string group;
    int beams = 0;
    int scans = 0;  ///< aligned scans used
    double scene_time_s = NAN;  ///< smoke state whose shape was scaled
    Estimate noise_floor;  ///< r.m.s. receiver noise [normalised power]
    double se_statistical = NAN;  ///< part of noise_floor.se from the counts (robust)
    double se_calibration = NAN;  ///< part from the calibration curve
    double variance_inflation = NAN;  ///< robust / model-based variance
    Estimate onset_column;  ///< column [density·m] where the fitted model errs half the time
    double pearson_chi2 = 0;
    int dof = 0;
};

/// @brief Fits the URG-04LX noise floor to the error counts of one group of an earlier threshold fit.
/// @param fit the threshold fit (its aligned scans, offset and groups)
/// @param group index into fit.groups
/// @param mount the sensor as placed in the scene (its other physical parameters are kept)
/// @throw Error when the sensor is not a URG-04LX.
UrgNoiseFloorResult fitUrgNoiseFloor(const Scene& scene, const SurfaceSet& surfaces, const SensorMount& mount,
                                     const SensorFitResult& fit, size_t group, const CurveFitResult& calibration,
                                     const UrgNoiseFloorConfig& cfg = {});

}  // namespace smokescan
