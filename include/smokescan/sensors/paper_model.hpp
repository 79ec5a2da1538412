#pragma once
/// @file paper_model.hpp
/// @brief The smoke paper's sensor model (Formsma et al. 2010, section 4.3), the baseline.
///
/// Parameters (PaperModelConfig, sensors/sensor_config.hpp): penetration_power 0.007 density·m
/// (the paper's 0.0028 × 2.5 m; USARSim's code used 0.00575), local_threshold 0.002 density.
///
/// Hokuyo: the beam consumes ∫ρ ds through regional smoke up to the surface (or up to its
/// maximum range when there is none); when that exceeds the penetration power it reports error
/// value 0. A beam that meets local smoke reports error value 0.
/// Sick: passes through regional smoke; local smoke is a solid obstacle at the distance where
/// the beam meets it.
#include "smokescan/sensor_config/sensor_config.hpp"
#include "smokescan/sensors/beam_result.hpp"

namespace smokescan {

/// @brief The URG-04LX's rule for one beam (sensors/urg04lx/paper_urg.cpp): error 0 for any local
/// smoke or a regional column over the penetration power, else the surface's range.
/// @param noise a standard normal draw (0: the noise-free reading)
BeamResult paperUrgBeam(const LrfSpec& spec, const PaperModelConfig& cfg, const SurfaceHit& hit, const BeamSmoke& smoke,
                        double noise);

/// @brief The LMS200's rule for one beam (sensors/lms200/paper_sick.cpp): local smoke is an obstacle
/// at the distance the beam meets it; regional smoke is seen through.
BeamResult paperSickBeam(const LrfSpec& spec, const SurfaceHit& hit, const BeamSmoke& smoke, double noise);

}  // namespace smokescan
