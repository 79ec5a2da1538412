#pragma once
/// @file lrf.hpp
/// @brief Datasheet geometry, range limits, noise and error values of the two laser range
/// finders of the smoke paper. Sources (SCIP 2.0, the LMS200 manual): docs/references.md; details in docs/sensors.md.
///
/// | field            | URG-04LX                         | LMS200                                   |
/// |------------------|----------------------------------|------------------------------------------|
/// | principle        | AMCW phase, 785 nm               | pulsed time of flight, 905 nm            |
/// | beams            | steps 44…725 (682), 360°/1024    | 181 at 1° or 361 at 0.5° over 180°       |
/// | beam angle       | (step − 384)·2π/1024, 0 = ahead  | 0 … π, π/2 = ahead (Sick's convention)   |
/// | range            | 0.02 … 5.6 m, 1 mm units         | 8 m mode: mm; 80 m mode: cm              |
/// | scan period      | 0.1 s                            | 0.0133 s (75 Hz at 1°)                    |
/// | noise σ          | 5 mm below 1 m, 0.5 % of range above | 5 mm (mm mode), 10 mm (cm mode)      |
/// | no return        | 0                                | 8183 raw (mm mode 8183 mm; cm mode 81830 mm) |
///
/// Noise: the URG-04LX datasheet gives accuracy ±10 mm (60 mm–1 m) and ±1 % (1–4 m); smokescan
/// takes that band as 2σ. The LMS200's statistical error is taken as 5 mm (1σ, mm mode).
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "smokescan/sensor_config/sensor_kind.hpp"

namespace smokescan {

struct LrfSpec {
    SensorType type = SensorType::Urg04lx;
    double wavelength_nm = 785;
    int n_beams = 0;
    double angle0_rad = 0;  ///< angle of beam 0
    double dangle_rad = 0;  ///< angle increment
    double range_min_m = 0.02;
    double range_max_m = 5.6;
    double unit_m = 0.001;  ///< reported range unit
    double scan_period_s = 0.1;
    long long no_return_code = 0;  ///< value reported when nothing is measured
    /// The reported values that are ranges; every value outside is an error code.
    long long first_range_value = 0, last_range_value = std::numeric_limits<long long>::max();
    double sigma_near_m = 0.005;  ///< noise σ below near_limit_m
    double near_limit_m = 1.0;
    double sigma_rel = 0.005;  ///< noise σ as a fraction of range beyond near_limit_m

    double angle(int i) const { return angle0_rad + i * dangle_rad; }
    double rangeSigma(double range_m) const
    {
        return range_m < near_limit_m ? sigma_near_m : std::max(sigma_near_m, sigma_rel * range_m);
    }
    /// True when a reported value is an error code, not a range.
    bool isErrorValue(long long value) const { return value < first_range_value || value > last_range_value; }
    /// True when a logged range [m] is one of the error values (a log gives them in its own unit).
    bool isErrorRange(double range_m) const { return isErrorValue(std::llround(range_m / unit_m)); }
    /// A reported value as a range [m]; NaN for an error value.
    double rangeOf(long long value) const { return isErrorValue(value) ? NAN : double(value) * unit_m; }
    /// Which values are error codes, in words (log headers).
    std::string errorValueSummary() const;
};

/// @brief The spec for a sensor's type and options (its kind's, sensor_config/laser_kind.hpp;
/// the two datasheets' in sensor_config/urg04lx.hpp and lms200.hpp).
struct SensorConfig;
LrfSpec specFor(const SensorConfig& config);

}  // namespace smokescan
