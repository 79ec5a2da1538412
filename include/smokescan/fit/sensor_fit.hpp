#pragma once
/// @file sensor_fit.hpp
/// @brief Fits a laser's smoke behaviour to recorded data, as the smoke paper's authors did by hand
/// for their BOCAS runs: the camera's clock offset, per surface the saturation threshold S* below
/// which its beams return error codes, the penetration power it implies, and the range bias and
/// noise as smoke thickens. Method and tests: docs/fitting.md.
///
/// Threshold: P(error | S) = F((S* − S)/w), F the normal CDF (probit) or the logistic; a sharp step
/// is the limit w → 0. Per scan, a surface's n beams give e errors (binomial); the fit is maximum
/// likelihood (Ceres minimises the deviance through signed deviance residuals), and JᵀJ of the
/// Pearson residuals at the solution is the Fisher information. Beams of one scan share their smoke
/// and scans within a camera frame share its noise, so the covariance is cluster-robust (sandwich)
/// over blocks of two camera frames.
/// The clock offset δ (camera time = laser time + δ) is a parameter of the same fit, started from
/// the best agreement between error onsets and saturation crossings over a grid.
///
/// | field            | default  | unit | meaning                                                      |
/// |------------------|----------|------|--------------------------------------------------------------|
/// | link             | probit   | –    | ErrorLink: probit or logistic                                |
/// | estimate_offset  | true     | –    | fit δ; false: δ = offset_s                                   |
/// | offset_s         | 0        | s    | fixed δ, or the centre of the search                          |
/// | offset_window_s  | 60       | s    | δ searched in offset_s ± this                                 |
/// | offset_step_s    | 0.1      | s    | grid step of the search (window/step at most 36000)           |
/// | min_beams        | 2        | –    | groups with fewer beams in the log are not fitted              |
/// | range_bins       | 8        | –    | saturation bins of the range bias/noise fit                    |
/// | clear_quantile   | 0.8      | –    | scans above this saturation quantile (and clear of S*) are clear air |
/// | sigma_t_per_density | 200   | 1/m  | extinction per unit density at the laser's wavelength (τ = σ_t·P) |
/// | reference        | ""       | –    | group whose threshold goes into the sensor file ("" = most beams) |
/// | smooth_s         | 2        | s    | the saturation is averaged over this window before fitting (its slope aligns the clocks) |
/// | bootstrap        | 30       | –    | replicates of the parametric bootstrap behind the errors on S* and δ: 0 (the analytic floor only) or 10…1000 |
#include <atomic>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "smokescan/calib/saturation_curve.hpp"
#include "smokescan/core/estimate.hpp"
#include "smokescan/fit/beam_groups.hpp"
#include "smokescan/io/recorded.hpp"
#include "smokescan/media/medium.hpp"
#include "smokescan/sensor_config/lrf.hpp"

namespace smokescan {

/// @brief The series averaged over a centred window of 2h + 1 samples (shrunk at the ends).
SaturationSeries movingAverage(const SaturationSeries& s, int h);
/// @brief The series' white-noise level: the MAD of its second differences (which have variance
/// 6σ² where the series is locally linear), as σ.
double saturationNoise(const SaturationSeries& s);

/// The threshold's link function F in P(error | S) = F((S* − S)/w).
enum class ErrorLink { Probit, Logistic };
/// @brief "probit" or "logistic".
const char* errorLinkName(ErrorLink link);

struct SensorFitConfig {
    ErrorLink link = ErrorLink::Probit;
    bool estimate_offset = true;
    double offset_s = 0;
    double offset_window_s = 60;
    double offset_step_s = 0.1;
    int min_beams = 2;
    int range_bins = 8;
    double clear_quantile = 0.8;
    double sigma_t_per_density = Medium::kCalibratedSigmaT;
    std::string reference;
    double smooth_s = 2.0;
    int bootstrap = 30;
    /// When set, another thread may stop the fit: it then throws Error ("stopped") soon.
    const std::atomic<bool>* stop = nullptr;
};

struct ThresholdFit {
    std::string group;
    int beams = 0, scans = 0;
    long long errors = 0, observations = 0;
    bool fitted = false;
    bool sharp = false;  ///< errors and clear scans separate perfectly: w → 0, S* in the gap
    std::string diagnosis;  ///< why not fitted, or what to beware of ("" = fine)
    Estimate S_star;
    Estimate width;  ///< the sensor's own width; the observed one is √(w² + σ_S²)
    double cov_S_star_width = 0;
    double range_m = 0;  ///< laser–surface distance used for P
    Estimate density;  ///< ρ(S*) through the calibration curve [density]
    Estimate penetration_power;  ///< ρ(S*)·range_m [density·m]
    Estimate tau;  ///< σ_t·P, the optical depth at the threshold
    double pearson_chi2 = 0, deviance = 0;
    double variance_inflation = NAN;  ///< robust / model-based variance of S* (correlated beams, frames)
    int bootstrap_fits = 0;  ///< replicates behind S*'s error (0: the analytic floor)
    int dof = 0;
};

/// Range bias and noise against the saturation drop x = S_ref − S (x ≥ 0 as smoke thickens):
/// bias(x) = bias0 + bias_slope·x, noise(x) = noise0 + noise_slope·x [m].
struct RangeFit {
    std::string group;
    bool fitted = false;
    std::string diagnosis;
    double S_ref = NAN;  ///< clear-air saturation
    Estimate bias0, bias_slope, noise0, noise_slope;
    double chi2_bias = 0, chi2_noise = 0;
    int dof = 0;
    struct Bin {
        double S = 0, x = 0, mean_m = 0, se_mean_m = 0, sd_m = 0, se_sd_m = 0;
        int n = 0;
    };
    std::vector<Bin> bins;
    long long observations = 0;
};

struct OffsetFit {
    bool estimated = false;
    Estimate offset_s;  ///< camera time − laser time
    int transitions = 0;  ///< error onsets and recoveries seen in the log
    std::vector<std::pair<double, double>> agreement;  ///< (δ, fraction of beams classified right)
    std::string diagnosis;
    int bootstrap_fits = 0;  ///< replicates behind the error (0: the analytic floor)
};

/// The two streams on the laser's scan times.
struct AlignedScan {
    double time_s = 0;  ///< laser clock
    double saturation = NAN;  ///< camera's saturation at time_s + δ (NaN outside its span)
    std::vector<int> errors, beams;  ///< per group
    std::vector<double> mean_range_m;  ///< per group, valid beams (NaN when none)
};

struct SensorFitResult {
    OffsetFit offset;
    std::vector<ThresholdFit> thresholds;  ///< per group
    std::vector<RangeFit> ranges;  ///< per group
    std::vector<AlignedScan> aligned;
    std::vector<BeamGroup> groups;
    std::vector<std::string> diagnoses;  ///< data-level problems
    double saturation_noise = 0;  ///< σ of the measured saturation (from its second differences)
    int smoothing_samples = 1;  ///< frames averaged per smoothed sample
    int reference = -1;  ///< index into thresholds for the sensor file (−1: none fitted)
    /// Replicates drawn for the errors on S* and δ (0: none); each estimate's bootstrap_fits says
    /// how many fitted.
    int bootstrap_replicates = 0;
    std::string error_method;  ///< where the errors on S* and δ come from ("" when nothing fitted)
    bool ok() const { return reference >= 0; }
};

/// Which readings failed, [scan][beam], for a sensor that has no error values: the omnicam, whose
/// failure is a reading off its truth (fit/omni_fit.hpp). Empty: the spec's error values decide.
using FailureMask = std::vector<std::vector<bool>>;

/// @brief Fits the sensor. Never throws for degenerate data: it diagnoses instead (no smoke event,
/// all errors, a run that never recovers, spans that do not overlap).
/// @param calibration the density ↔ saturation curve (null: P and τ are not computed)
/// @param failed which readings failed (empty: the error values of `spec`); a failed reading is
/// an error of its group and stays out of the range fit
/// @throw Error for a bad configuration, or a mask whose shape is not the log's.
SensorFitResult fitSensor(const RecordedLog& log, const SaturationSeries& sat, const std::vector<BeamGroup>& groups,
                          const LrfSpec& spec, const CurveFitResult* calibration, const SensorFitConfig& cfg = {},
                          const FailureMask& failed = {});

/// @brief Saturation at time t by linear interpolation; NaN outside the series' span.
double saturationAt(const SaturationSeries& s, double t_s);

}  // namespace smokescan
