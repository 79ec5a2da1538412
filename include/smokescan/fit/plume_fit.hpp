#pragma once
/// @file plume_fit.hpp
/// @brief A Sick LMS200 in smoke plumes: the reported distance as a function of the plume's
/// density (how far the beam penetrates before the smoke echoes), from a recorded log and the
/// scene's smoke at each scan time (docs/fitting.md, "Sick in plumes").
///
/// Per beam and scan whose path crosses local smoke before its surface, the scene gives the
/// entry r_in (first point where the density reaches entry_fraction of its peak on the beam)
/// and the peak density ρ. The log gives the outcome: a smoke echo (a range shorter than the
/// surface by more than surface_margin_m), the surface, or an error value. Two Ceres fits:
///  - penetration depth d = r − r_in of smoke echoes: ln d = ln D − k·ln(ρ/ρ_ref), ρ_ref the
///    median peak density of the echoes; errors scaled by χ²/dof (the scatter is not known a priori);
///  - share of beams that see the plume as an obstacle: logistic in ln ρ with midpoint ρ_50 and
///    slope s, on density bins with binomial weights.
/// The paper's model puts every Sick echo at the plume's edge (d = 0 beyond a density); a
/// physical Sick reads deeper into thin plumes (k > 0).
///
/// | field             | default | unit | meaning                                                  |
/// |-------------------|---------|------|----------------------------------------------------------|
/// | time_offset_s     | 0       | s    | scene time = log time + this                             |
/// | entry_fraction    | 0.05    | –    | the plume starts where density reaches this share of its peak |
/// | surface_margin_m  | 0.05    | m    | a range this much short of the surface is a smoke echo    |
/// | min_depth_m       | 0.01    | m    | depths are floored here before the logarithm              |
/// | bins              | 8       | –    | log-density bins of the tables and the logistic fit       |
#include <string>
#include <vector>

#include "smokescan/fit/sensor_fit.hpp"
#include "smokescan/io/recorded.hpp"
#include "smokescan/scene/scene.hpp"
#include "smokescan/scene/surfaces.hpp"

namespace smokescan {

struct PlumeFitConfig {
    double time_offset_s = 0;
    double entry_fraction = 0.05;
    double surface_margin_m = 0.05;
    double min_depth_m = 0.01;
    int bins = 8;
};

/// One beam of one scan that crossed a plume.
struct PlumeObservation {
    double time_s = 0, angle_rad = 0;
    double peak_density = 0;  ///< [density]
    double entry_m = 0;  ///< r_in [m]
    double surface_m = 0;  ///< distance to the surface (or the range limit) [m]
    double range_m = NAN;  ///< reported range (NaN for an error value)
    enum Outcome { SmokeEcho, Surface, ErrorValue } outcome = ErrorValue;
};

struct PlumeFitResult {
    bool ok = false;
    std::vector<std::string> diagnoses;
    std::vector<PlumeObservation> obs;
    double rho_ref = NAN;  ///< [density]
    Estimate depth_m;  ///< D: penetration depth at rho_ref [m]
    Estimate exponent;  ///< k
    double cov_lnD_k = 0;
    double depth_chi2 = 0;  ///< of ln d, before scaling
    int depth_dof = 0;
    Estimate rho_50;  ///< density where half the beams echo from the smoke [density]
    Estimate slope;  ///< logistic slope in ln ρ
    double share_chi2 = 0;
    int share_dof = 0;
    struct Bin {
        double rho_lo = 0, rho_hi = 0;
        int n = 0, echo = 0, surface = 0, error = 0;
        double mean_depth_m = NAN, se_depth_m = NAN;
    };
    std::vector<Bin> bins;
};

/// @brief Fits the Sick's penetration into the scene's plumes to a recorded log.
/// @param mount the Sick as placed in the scene (its pose and range mode)
/// @throw Error when the sensor is not an LMS200 or the scene has no local smoke.
PlumeFitResult fitSickPlume(const RecordedLog& log, const Scene& scene, const SurfaceSet& surfaces,
                            const SensorMount& mount, const PlumeFitConfig& cfg = {});

/// @brief The fitted penetration depth at peak density rho [m], with its error (delta method).
Estimate plumeDepthAt(const PlumeFitResult& r, double rho);

}  // namespace smokescan
