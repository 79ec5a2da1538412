#pragma once
/// @file paper_model.hpp
/// @brief The smoke paper's sensor model (Formsma et al. 2010, section 4.3), the baseline.
///
/// | parameter          | default | unit       | meaning                                           |
/// |--------------------|---------|------------|---------------------------------------------------|
/// | penetration_power  | 0.007   | density·m  | the paper's 0.0028 × 2.5 m; USARSim's code used 0.00575 |
/// | local_threshold    | 0.002   | density    | local (plume) density at which a beam counts as meeting a particle |
///
/// Hokuyo: the beam consumes ∫ρ ds through regional smoke up to the surface (or up to its
/// maximum range when there is none); when that exceeds the penetration power it reports error
/// value 0. A beam that meets local smoke reports error value 0.
/// Sick: passes through regional smoke; local smoke is a solid obstacle at the distance where
/// the beam meets it.
#include "smokescan/media/smoke.hpp"
#include "smokescan/scene/surfaces.hpp"
#include "smokescan/sensors/lrf.hpp"

namespace smokescan {

struct PaperModelConfig {
    double penetration_power = 0.007;
    double local_threshold = 0.002;
};

/// What one beam reports, and why.
struct BeamResult {
    long long value = 0;     ///< reported value in the sensor's unit: a range or an error code
    bool error = false;      ///< value is an error code
    double true_range_m = kInf;  ///< noiseless distance of what was measured (surface or smoke)
    SurfaceHit hit;          ///< first surface in clear air (up to the sensor's maximum range)
    BeamSmoke smoke;         ///< smoke met up to the surface (or maximum range)
    const char* cause = "ok";  ///< why: "ok", or the error's cause (docs/sensors.md)
    double power = 0;        ///< physical model: received amplitude (normalised power)
};

/// @brief Marks r as an error: `code` in the sensor's unit, and why.
BeamResult& markError(BeamResult& r, long long code, const char* cause);

/// @brief Reports a measured distance the way the sensor does: outside its window → its no-return
/// value; else range_m plus the datasheet noise (`noise` a standard normal), rounded to the unit,
/// again refused when that lands on an error value. Shared by the paper and physical models.
BeamResult& reportRange(const LrfSpec& spec, double range_m, double noise, BeamResult& r);

/// @brief Applies the paper model to one beam. `noise` is a standard normal draw.
BeamResult paperBeam(const LrfSpec& spec, const PaperModelConfig& cfg, const SurfaceHit& hit,
                     const BeamSmoke& smoke, double noise);

}  // namespace smokescan
