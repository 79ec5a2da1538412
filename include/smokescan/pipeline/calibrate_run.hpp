#pragma once
/// @file calibrate_run.hpp
/// @brief `smokescan calibrate` as one library call: the density ↔ saturation curve (the smoke
/// paper's Fig. 7) from the scene's own rendered frames, its sweep bounded before any frame is
/// rendered. CalibrateConfig (calib/calibration.hpp) in, CalibrationResult out.
#include "smokescan/calib/calibration.hpp"
#include "smokescan/pipeline/run_control.hpp"

namespace smokescan {

/// @brief Checks the sweep (at most limits::kCalibrationDensities densities in [0,
/// limits::kCalibrationDensityMax], at most limits::kFrameSamples samples in all), renders it and
/// fits the curve. @param control progress after each frame (done, total); cancel before each
/// @throw Error naming the option at fault or when the curve cannot be fitted; Cancelled
CalibrationResult runCalibration(const Scene& scene, const CalibrateConfig& cfg, const RunControl& control = {});

}  // namespace smokescan
