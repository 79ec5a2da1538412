#pragma once
/// @file lidar_fit.hpp
/// @brief What a 3D lidar's recorded intensities say of the scene's surfaces and of its receiver
/// (`smokescan fit --points`, docs/lidar.md "Fitted from the intensities"): on the beams the
/// replay is sure of (LidarTally's clear beams, answered at their surface), each surface's
/// reflectance factor k — the scene's NIR reflectance times k gives the recorded echoes — and
/// the scatter s of the intensities about the fit in the replay's noise (1: the preset's
/// receiver noise explains it).
///
/// The intensity is 100·P·R²/O(R) of the echo's peak P at its recorded range R. The recorded
/// intensity brought to the replay's range, y = I_rec·(R_exp/R_rec)², reads the recorded peak
/// (the range's noise taken out). At factor k the replay's peak is P(1)·g(k), g the parabola
/// through the replay's peaks at ¼, ½ and 1 times the surface's power (k for an echo alone; the
/// smoke's backscatter under the echo does not scale; scaleAt). So y = I_exp·g(k) + noise of sd
/// u = I_exp·peak_noise / peak_sd (the peak's noise, as the receiver's log-parabola through
/// its samples carries it). Least squares on (y − I_exp·g(k))/u (Ceres), each surface's k with
/// its covariance from the model's (JᵀJ)⁻¹ times its own residuals' mean square.
/// A beam is used when g's slope is min_slope at least at ¼ and at 1 (an echo mostly the
/// surface's), when at
/// the fitted factor its echo peaks min_peak_sd noise sd at least (fainter echoes read high:
/// the peak taken from noisy samples, 2 % at 16 sd, 0.5 % at 30–45 sd, measured on the
/// receiver's model) and its intensity stays under max_intensity (the sensor caps it at 255),
/// and when its residual lies within clip_sd robust sd (1.4826·MAD) of its surface's median
/// residual (a faint echo the noise lifts beside the surface's, an echo the replay's geometry
/// gets wrong: a few in 10⁴ in the factory). The factors and the beams used are
/// found together, from k = 1, until neither moves.
///
/// The factors come out of their own scene's frames unbiased to parts in 10⁴ (at most +1.6·10⁻⁴,
/// the tank at 38 s, over 10 seeds in the factory's thin and thick smoke; LidarFit.TheScenesOwn…):
/// each factor's statistical error (factor_se) goes beside a systematic one of
/// kIntensitySystematic of it (factor_sys), which a fit of ten thousand beams (statistical
/// errors of 10⁻⁶) would otherwise undercut.
///
/// | field         | default | unit | meaning                                                   |
/// |---------------|---------|------|-----------------------------------------------------------|
/// | min_beams     | 30      | –    | a surface is fitted from this many usable beams at least   |
/// | min_peak_sd   | 50      | –    | a beam's echo at the fitted factor peaks this many noise sd at least |
/// | min_slope     | 0.5     | –    | g's slope at ¼ and at 1 (the peak's share that scales with the surface's power) at least |
/// | max_intensity | 200     | %    | a beam's intensity at the fitted factor stays under this   |
/// | clip_sd       | 6       | –    | a beam's residual stays within this × its surface's robust sd |
#include <cstdint>
#include <vector>

namespace smokescan {

/// One clear beam answered at its surface: the surface its central ray hits, the recorded and
/// replayed intensities and ranges, the replayed echo's peak in noise sd and against the power.
struct LidarIntensitySample {
    int surface = -1;  ///< Scene::surfaces index
    float recorded = 0, recorded_range_m = 0;  ///< the recorded point's intensity [%] and range [m]
    float expected = 0, range_m = 0;  ///< the replay's
    float peak_sd = 0;  ///< the replayed echo's peak / the receiver's noise sd
    float peak_noise = 1;  ///< the peak's noise in noise sd (ExpectedBeam::peak_noise)
    /// The replayed peak at a half and a quarter of the surface's power, over its own
    /// (ExpectedBeam::peak_at_half, peak_at_quarter): ½ and ¼ for an echo alone.
    float at_half = 0.5f, at_quarter = 0.25f;
    /// @brief The replayed peak at factor k over its own: the parabola through (¼, at_quarter),
    /// (½, at_half) and (1, 1) between ¼ and 1, drawn on beyond each end along its tangent there.
    template <class T>
    T scaleAt(const T& k) const
    {
        // Lagrange's form on the nodes ¼, ½, 1, its derivative at the ends.
        const double q = at_quarter, h = at_half;
        auto value = [&](const T& x) {
            return T(q) * (x - T(0.5)) * (x - T(1)) / T(0.1875) - T(h) * (x - T(0.25)) * (x - T(1)) / T(0.125) +
                (x - T(0.25)) * (x - T(0.5)) / T(0.375);
        };
        auto slope = [&](double x) {
            return q * (2 * x - 1.5) / 0.1875 - h * (2 * x - 1.25) / 0.125 + (2 * x - 0.75) / 0.375;
        };
        if (k > T(1)) return T(1) + (k - T(1)) * T(slope(1));
        if (k < T(0.25)) return T(q) + (k - T(0.25)) * T(slope(0.25));
        return value(k);
    }
};

/// The relative systematic error of a fitted factor (see above).
inline constexpr double kIntensitySystematic = 3e-4;

struct LidarFitConfig {
    long long min_beams = 30;
    double min_peak_sd = 50;
    double min_slope = 0.5;
    double max_intensity = 200;
    double clip_sd = 6;
};

/// One surface's reflectance factor.
struct SurfaceReflectanceFit {
    int surface = -1;  ///< Scene::surfaces index
    long long beams = 0;  ///< beams used
    long long candidates = 0;  ///< its clear beams answered at it (LidarIntensitySample), usable or not
    double factor = 1, factor_se = 0;  ///< k and its statistical standard error
    double factor_sys = 0;  ///< its systematic error: kIntensitySystematic · k
    double scatter = 0;  ///< its own residuals' rms in noise sd
    bool fitted = false;  ///< false: fewer than min_beams usable beams
};

/// The scatter [noise sd] above which a fitted surface's intensities are not its factor times
/// the replay's: the surfaces of the recorded room read 0.9–1.3 (tests/test_lidar_fit.cpp), a
/// glossy wall hundreds, as does a scene that is not the recording's.
constexpr double kMisfitScatter = 3;
/// @brief Whether a fitted surface's factor leaves its intensities unexplained (kMisfitScatter).
inline bool misfits(const SurfaceReflectanceFit& f) { return f.fitted && f.scatter > kMisfitScatter; }

struct LidarFitResult {
    std::vector<SurfaceReflectanceFit> surfaces;  ///< every surface with samples, by index
    long long beams = 0;  ///< beams used in all
    double scatter = 0, scatter_se = 0;  ///< s: the pooled residuals' rms in noise sd, and its error
    /// The recorded intensities' step: 1 when every one is a whole number (a sensor that reports
    /// them so, e.g. a VLP-16), whose rounding (variance 1/12) joins each beam's noise; else 0.
    double quantum = 0;
    int rounds = 0;  ///< fits until the beams used settled
};

/// @brief Fits each surface's reflectance factor and the intensities' scatter.
/// @throw Error when no surface has min_beams usable beams.
LidarFitResult fitLidarIntensities(const std::vector<LidarIntensitySample>& samples, const LidarFitConfig& cfg = {});

}  // namespace smokescan
