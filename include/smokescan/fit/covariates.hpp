#pragma once
/// @file covariates.hpp
/// @brief Per beam and scan of a recorded run, what the simulation knows about it, beside what
/// the sensor reported: the table in which the residuals between measured and simulated data are
/// searched for what the simulation gets wrong.
///
/// Columns: time_s (laser clock = scene clock), beam, angle_rad, group, measured_m (NaN for an
/// error), error (0/1), saturation (camera, aligned), surface, material, incidence_deg,
/// surface_range_m (clear-air distance to the surface hit, NaN for none), column_density_m (∫ρ ds
/// up to it), tau (optical depth at the laser's wavelength up to it).
#include <string>

#include "smokescan/fit/sensor_fit.hpp"
#include "smokescan/scene/scene.hpp"
#include "smokescan/scene/surfaces.hpp"

namespace smokescan {

/// @brief Writes the covariate table (CSV, atomically).
/// @param all_beams every beam of the log; false: only beams of the fit's groups
void writeCovariates(const std::string& path, const RecordedLog& log, const SensorFitResult& fit, const Scene& scene,
                     const SurfaceSet& surfaces, const SensorMount& mount, const LrfSpec& spec, bool all_beams = false);

}  // namespace smokescan
