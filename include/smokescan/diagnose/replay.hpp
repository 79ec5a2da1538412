#pragma once
/// @file replay.hpp
/// @brief A recorded run replayed beam by beam: every logged beam with what the simulation knows
/// of it (its surface, distance, incidence, the smoke column along it at each scan) beside what the
/// sensor reported. The smoke is the measured one: at each scan time the scene's regional smoke is
/// scaled so that the camera's predicted target saturation equals the recorded saturation (through
/// the calibration curve); where it lies along each beam is the scene's densest state's shape
/// (`reference`), or the scene's own state at each scan (`timeline`, for smoke that changes shape:
/// puffs, a drifting cloud). Without a saturation series the scene's own time line is traced.
///
/// | field          | default   | unit | meaning                                                     |
/// |----------------|-----------|------|-------------------------------------------------------------|
/// | offset_s       | 0         | s    | camera clock − laser clock (the saturation is read at t + offset) |
/// | block_s        | 3         | s    | time block of the held-out split and of the covariance, at most: shorter while the smoke changes (kBlockMove) |
/// | camera         | ""        | –    | the scene camera that saw the target ("" = the first)        |
/// | target_prefix  | "target_" | –    | the camera's target surfaces                                 |
/// | time_step_s    | 1         | s    | step of the search for the scene's densest smoke state       |
/// | smooth_s       | 0         | s    | the saturation is averaged over this window (0: raw; its noise widens the threshold) |
/// | shape          | reference | –    | where the camera's smoke lies along each beam (SmokeShape)  |
///
/// The saturation's own noise (its white-noise level, shrunk by the smoothing) makes each scan's
/// density uncertain: its standard error in ln(density) is kept per scan, and the predictive
/// model widens the threshold by it.
#include <atomic>
#include <string>
#include <vector>

#include "smokescan/diagnose/predictive.hpp"
#include "smokescan/fit/fit_inputs.hpp"
#include "smokescan/sensor_config/lrf.hpp"
#include "smokescan/sensor_config/sensor_config.hpp"

namespace smokescan {

/// A block ends early once the smoke's density has moved by this share of the run's densest.
constexpr double kBlockMove = 0.025;
/// ...but never before it has lasted this long [s].
constexpr double kMinBlock_s = 0.5;
/// A reference shape that misstates the scene's own columns by this much (Replay::shape_error_ln)
/// is reported: the estimates read against it are attenuated.
constexpr double kShapeWarningLn = 0.2;

/// Where the camera's measured smoke lies along each beam (its amount is always the camera's).
enum class SmokeShape {
    /// The scene's densest state scaled by the camera's density over that state's: one shape for
    /// the whole run, whatever the scene's time line says (robust to a time line that is wrong).
    Reference,
    /// The scene's state at each scan: its volumes the camera sees scaled by the camera's density
    /// over theirs at that scan (ε-regularised, Replay::shape_floor), the rest as the scene has
    /// it. For smoke whose shape changes, when the scene's time line says where it is.
    Timeline,
};

/// @brief A shape's name: reference or timeline.
const char* smokeShapeName(SmokeShape s);
/// @brief The shape named `name`. @throw Error naming `key` (an option) for any other name.
SmokeShape smokeShapeOf(const std::string& name, const std::string& key);

struct ReplayConfig {
    double offset_s = 0;
    double block_s = 3;
    std::string camera, target_prefix = "target_";
    double time_step_s = 1.0;
    double smooth_s = 0.0;
    SmokeShape shape = SmokeShape::Reference;
    /// When set, another thread may stop the replay: it then throws Error ("stopped") soon.
    const std::atomic<bool>* stop = nullptr;
};

/// What the simulation knows of one beam of the log (the same for every scan).
struct ReplayBeam {
    int surface = -1;  ///< scene surface index; −1: nothing within range
    double range_m = 0;  ///< distance to the surface (or the sensor's maximum range)
    double angle_rad = 0;  ///< beam angle in the sensor's convention
    double incidence_rad = 0;  ///< angle between the beam and the surface normal
    double column_ref = 0;  ///< regional smoke column to the surface in the reference state [density·m]
    double sight_m = 0;  ///< the smoke is integrated over this length of the beam's ray: the range (the
        ///< omnicam: its line of sight to the obstacle's foot) [m]
    double sigma_m = 0;  ///< a clear reading's noise σ [m]; 0: the sensor's datasheet noise at range_m
};

/// One scan: its time, the smoke it saw, its block.
struct ReplayScan {
    double time_s = 0;
    double saturation =
        NAN;  ///< the camera's, at time_s + offset (NaN: no saturation series, the scene's time line traced)
    double density = 0;  ///< the camera's density (saturation through the curve) [density]
    bool rising = false;  ///< the density is rising at this scan (beyond its noise; a plateau is not)
    double ln_density_sd = 0;  ///< standard error of ln(density) from the saturation's noise
    int block = 0;  ///< time block (at most block_s; shorter while the smoke changes)
    double scene_density = 0;  ///< SmokeShape::Timeline: the camera's density of the scene's seen volumes at time_s
};

struct Replay {
    LrfSpec spec;
    SensorConfig config;
    std::vector<std::string> surface_names;  ///< scene surface names, by index
    std::vector<ReplayBeam> beams;
    std::vector<ReplayScan> scans;
    std::vector<std::vector<float>> range_m;  ///< recorded [scan][beam] [m]; NaN = an error value
    /// The camera's density over camera time (for a clock offset): samples of the saturation
    /// series through the curve, on laser time (offset removed).
    std::vector<double> density_time_s, density_series;
    std::vector<double> density_ln_sd;  ///< each sample's standard error of ln(density) (lnDensitySdAt)
    double density_ref = 1;  ///< the camera's density in the reference state
    double saturation_noise = 0;  ///< the smoothed saturation's noise σ
    SaturationCurve curve;  ///< the calibration curve the saturation is read through
    int smooth_h = 0;  ///< the smoothing's half-width [camera samples]
    double frame_s = 1;  ///< the camera's median frame interval [s]
    double offset_s = 0;  ///< the camera clock − laser clock the replay assumed [s]
    /// The model diagnosed: the config's extensions (its sensor file's), with offset_s as their
    /// clock offset.
    ModelExtensions prior;
    bool from_saturation = true;
    SmokeShape shape = SmokeShape::Reference;
    /// Timeline: ε of the camera-to-scene density ratio (ρ + ε)/(ρ_scene + ε), 1 % of the
    /// reference density (the seen volumes' columns vanish with ρ_scene where the ratio is noise).
    double shape_floor = 0;
    /// How far the reference shape misstates the scene's own columns over its time line: the rms
    /// of ln((reference + c)/(timeline + c)) over beams whose column reaches P/5 (c = P/20, P the
    /// paper model's penetration power; up to 100 scans). Near 0: the smoke keeps its shape; 0.2
    /// or more: estimates from the reference shape are attenuated (docs/diagnosis.md, known limits).
    double shape_error_ln = 0;
    std::vector<std::vector<float>>
        column;  ///< traced columns [scan][beam]: without saturation, or timeline's seen volumes
    std::vector<std::vector<float>> column_unseen;  ///< timeline: the volumes the camera does not see [scan][beam]

    /// The physical model's replay (config.model physical, the URG-04LX's): per beam, the
    /// model's error probability, noise-free range [m] and a valid reading's standard deviation
    /// [m] against u = ln s, s the regional smoke's scale against the reference state, on the grid
    /// u_lo + j·du (j < grid), and at s = 0. Between grid points each is a monotone cubic in u
    /// (its tangents below): the likelihood is smooth in a threshold's shift, as the model is, not
    /// kinked at every grid point (a scan's beams share u, so their kinks added up to ruggedness
    /// larger than a threshold's standard error).
    struct PhysicalTable {
        double u_lo = 0, du = 0;
        int grid = 0;
        std::vector<double> err, range, sd;  ///< [beam · grid + j]
        /// Their tangents d/du at each grid point (Fritsch–Carlson: no overshoot between points,
        /// 0 at the top; at the bottom the clear-air branch's slope when it has the first
        /// secant's sign and at most 3 times it, else a kink there) [beam · grid + j]
        std::vector<double> err_slope, range_slope, sd_slope;
        std::vector<double> err_clear, range_clear, sd_clear;  ///< [beam]
        /// The last grid point k ≥ j with err[j..k] flat (max − min < 1e-12) [beam · grid + j], and
        /// the last with the clear value and err[0..k] flat [beam] (−1: err[0] differs from it).
        std::vector<int> flat_reach, flat_reach_clear;
    } physical;
    bool isPhysical() const { return config.model == SensorModel::Physical; }

    /// @brief The regional column along beam b at scan k [density·m] were the camera's density
    /// `density` (a double or a Ceres Jet: a clock offset reads it at another time).
    template <class T>
    T columnWith(size_t k, size_t b, const T& density) const
    {
        if (!from_saturation) return T(double(column[k][b]));
        if (shape == SmokeShape::Timeline)
            return T(double(column[k][b])) * (density + T(shape_floor)) / T(scans[k].scene_density + shape_floor) +
                T(double(column_unseen[k][b]));
        return density / T(density_ref) * T(beams[b].column_ref);
    }
    /// @brief The regional column along beam b at scan k [density·m].
    double columnAt(size_t k, size_t b) const { return columnWith(k, b, scans[k].density); }
    /// @brief The camera's density at laser time t [density], linear between samples; T a double
    /// or a Ceres Jet (a clock offset is differentiated through it).
    template <class T>
    T densityAt(const T& t) const;
    int blocks() const { return scans.empty() ? 0 : scans.back().block + 1; }
    /// @brief The densities the camera's saturation at laser time t reads as at S ∓ its noise
    /// there (σ_S left between two samples; the curve's floor included): {lower, upper} [density].
    std::pair<double, double> densityBandAt(double t) const;
    /// @brief The standard error of ln(density) read at laser time t: at each camera sample
    /// ½·ln(upper/lower) of its S ± σ_S through the curve (ln(upper/ρ) where the lower reads clear
    /// air; 0 in clear air), between samples interpolated and shrunk by the noise left there.
    double lnDensitySdAt(double t) const;
};

/// @brief Replays a run. @throw Error naming the log when its beams do not match the sensor's,
/// the saturation when it does not overlap the log, or the sensor file when its extensions name
/// a surface the scene does not have; and for the physical model of the LMS200 or without a
/// saturation series (not replayed).
Replay replayRun(const FitInputs& in, const SensorConfig& config, const ReplayConfig& cfg);

/// @brief Replays the omnicam rangefinder's log (fit/omni_fit.hpp) as a sensor with the omnicam
/// file's penetration power along each line of sight. Per scanline: the truth's obstacle and
/// distance, the smoke along the camera's line of sight to the obstacle's foot, a clear reading's
/// noise of one pixel's metric error there; a reading that is ok or short is a range, one that is
/// long (an obstacle missed) is the omnicam's "no return". @throw Error as replayRun does.
struct OmniFitInputs;
struct OmniSensorFile;
Replay replayOmniRun(const OmniFitInputs& o, const OmniSensorFile& file, const ReplayConfig& cfg);

template <class T>
T Replay::densityAt(const T& t) const
{
    const auto& ts = density_time_s;
    double td;
    if constexpr (std::is_same_v<T, double>)
        td = t;
    else
        td = t.a;
    if (ts.empty()) return T(0.0);
    if (ts.size() == 1 || td <= ts.front()) return T(density_series.front());
    if (td >= ts.back()) return T(density_series.back());
    const size_t i = size_t(std::upper_bound(ts.begin(), ts.end(), td) - ts.begin()) - 1;
    const double dt = ts[i + 1] - ts[i];
    if (!(dt > 0)) return T(density_series[i]);
    return T(density_series[i]) + T(density_series[i + 1] - density_series[i]) * (t - T(ts[i])) / T(dt);
}

}  // namespace smokescan
