#pragma once
/// @file physical_model.hpp
/// @brief The physical laser return model: the lidar equation per beam, then each sensor's own
/// way of turning the received signal into a range or an error value.
///
/// A beam's signal is a list of echoes (range, power), from three kinds of scatterer:
///  - surfaces hit by the sub-rays of the footprint: π·f_r(θ)·cos θ·O(R)/R²·T²(R), with f_r the
///    monostatic BRDF (Lambert at the sensor's wavelength plus the material's GGX lobe);
///  - smoke along the beam, in bins: π·β(r)·O(r)/r²·T²(r)·Δr, weighted by the part of the
///    footprint not yet stopped by a surface;
///  - the mirror path of a specular surface: the beam's specular part travels on, is
///    backscattered by smoke (or returned by a surface) and comes back the same way. The sensor
///    sees it at R + u, beyond the surface (docs/sensors.md: why the gold paper reads long).
/// The URG-04LX (AMCW) reports the phase of the sum of all echoes; the LMS200 (pulsed) detects
/// the first echo in the waveform. Both choose their error values by cause.
#include <vector>

#include "smokescan/media/density_grid.hpp"
#include "smokescan/media/smoke.hpp"
#include "smokescan/scene/scene.hpp"
#include "smokescan/scene/surfaces.hpp"
#include "smokescan/sensor_config/lrf.hpp"
#include "smokescan/sensor_config/physical_params.hpp"
#include "smokescan/sensors/beam_result.hpp"

namespace smokescan {

class KeyedRng;

enum class EchoSource { Surface, Smoke, Mirror };

struct Echo {
    double range_m = 0;  ///< apparent range (half the path length) [m]
    double power = 0;  ///< normalised received power (white Lambertian at 1 m = 1)
    EchoSource source = EchoSource::Surface;
};

/// Everything a beam sends back, before the sensor's electronics.
struct BeamSignal {
    std::vector<Echo> echoes;  ///< sorted by range
    double surface_power = 0, smoke_power = 0, mirror_power = 0;
    bool surface_in_range = false;  ///< some sub-ray hit a surface within the sensor's range
    /// The footprint's sub-rays did not all meet the same surface (an edge, a corner, a gap):
    /// the echo mixes what they met.
    bool mixed_surfaces = false;
    /// The smoke's backscatter power on points k·c, c = smoke_cell_m, when the sensor sums it on a
    /// grid (PhysicalParams::smoke_cell_m > 0): each piece of the path between two points shared
    /// between them so that its centre stays; empty otherwise, and the smoke is in `echoes`.
    std::vector<double> smoke_cells;
    double smoke_cell_m = 0;
    size_t smoke_first = 0;  ///< smoke_cells[k] is 0 for every k below this (the smoke starts there)

    /// Empty, as constructed, keeping the vectors' storage for the next beam.
    void clear()
    {
        echoes.clear();
        smoke_cells.clear();
        surface_power = smoke_power = mirror_power = 0;
        surface_in_range = mixed_surfaces = false;
        smoke_cell_m = 0;
        smoke_first = 0;
    }
};

/// Optical depth along a beam from a piecewise-constant σ_t profile: τ(r) in O(log n).
class TauProfile {
public:
    /// The profile is referred to, not copied: it must outlive this.
    explicit TauProfile(const std::vector<ProfileSegment>& sigma_t);
    explicit TauProfile(std::vector<ProfileSegment>&&) = delete;
    /// The same with τ's running sums in `storage` (its capacity reused, as a beam loop does; it
    /// must outlive this, and no other live TauProfile may use it).
    TauProfile(const std::vector<ProfileSegment>& sigma_t, std::vector<double>& storage);
    TauProfile(std::vector<ProfileSegment>&&, std::vector<double>&) = delete;
    TauProfile(const TauProfile&) = delete;
    TauProfile& operator=(const TauProfile&) = delete;
    double tau(double r_m) const;
    double sigmaAt(double r_m) const;  ///< σ_t [1/m] at r (0 outside the segments)
    /// Where the stretch of constant σ_t holding r ends [m]: its segment's end, the next
    /// segment's start in a gap, +inf beyond the last.
    double stretchEnd(double r_m) const;
    /// The σ_t segments, in order along the beam.
    const std::vector<ProfileSegment>& segments() const { return seg_; }

private:
    const std::vector<ProfileSegment>& seg_;
    std::vector<double> own_;  ///< the sums' storage when none is given
    std::vector<double>& cum_;  ///< τ at each segment's start
};

/// @brief The material's diffuse reflectance in the sensor's band (785 or 905 nm).
double nirReflectance(const Material& m, double wavelength_nm);

/// @brief Monostatic BRDF f_r [1/sr] of a material at the given wavelength, for light leaving
/// and returning along the same direction at incidence cos θ.
double monostaticBrdf(const Material& m, double wavelength_nm, double cos_theta);

/// @brief Power of a surface echo: π·f_r·cos θ·O(R)/R²·T², T² = exp(−2τ).
double surfaceEchoPower(const PhysicalParams& p, const Material& m, double wavelength_nm, double cos_theta,
                        double range_m, double tau_to_surface);

/// A piece of a beam's path in smoke of constant σ_t: what the smoke's points need of T² over it.
struct SmokePiece {
    double step;  ///< T² at its end over T² at its start: exp(−2σ·len)
    double integral_m;  ///< ∫T² over the piece over T² at its start: (1 − exp(−2σ·len))/(2σ) [m]
    double centre_m;  ///< the centre of T² over the piece, from its start [m]
};

/// @brief A piece of length len_m [m] in smoke of extinction sigma_t [1/m] (0 allowed): from
/// the series in h = 2σ·len where h < 0.03 (the closed forms cancel there), else the closed forms.
SmokePiece smokePiece(double sigma_t, double len_m);

/// @brief Appends smoke echoes for the path s ∈ [s0, s1] of a beam whose σ_t and β profiles
/// are given in path coordinates s.
/// @param range_offset_m added to s to make the apparent range (the mirror path's R)
/// @param gain multiplies every echo (footprint weight, mirror reflectance², T² to the path start)
/// @param lobe_ratio Ω_lobe/Ω_beam of the mirror's specular lobe (0 on the direct path): the
///        geometric factor is 1/((R+u)² + u²·lobe_ratio), the mirror image (1/(R+u)²) for a smooth
///        mirror, the rough lobe's (Ω_beam/Ω_lobe)/u² for a wide one
/// @param blocked sorted distances at which each of the footprint's sub-rays stops (may be empty)
void appendSmokeEchoes(const PhysicalParams& p, const TauProfile& tau, const std::vector<ProfileSegment>& beta,
                       double s0, double s1, double range_offset_m, double gain, double lobe_ratio,
                       const std::vector<double>& blocked, EchoSource source, BeamSignal& out);

/// @brief The smoke's backscatter along s ∈ [0, s1] of the direct path summed onto points at the
/// multiples of p.smoke_cell_m (out.smoke_cells): the path cut at the points and where sub-rays
/// stop, T² integrated exactly over each piece, O(r)/r² at its middle, its power shared between
/// the two points around it in proportion to their nearness (its centre kept).
/// @param blocked sorted distances at which each of the footprint's sub-rays stops (may be empty)
void depositSmokeCells(const PhysicalParams& p, const TauProfile& tau, const std::vector<ProfileSegment>& beta,
                       double s1, const std::vector<double>& blocked, BeamSignal& out);

/// @brief Traces a beam's footprint (sub-rays) through the surfaces and the smoke and collects
/// its echoes: surfaces, smoke along the central ray, and mirror paths of specular surfaces.
/// @param central_hit, central_smoke receive the central ray's surface hit and smoke (may be null)
BeamSignal traceBeamSignal(const Ray& ray, const LrfSpec& spec, const PhysicalParams& p, const Scene& scene,
                           const SurfaceSet& surfaces, const SmokeField& field, SurfaceHit* central_hit,
                           BeamSmoke* central_smoke);
/// @brief The same for any sensor: its wavelength [nm] and the range [m] it reports to.
/// @param reflectance_factor per surface (Scene::surfaces index; null: all 1): each surface's NIR
/// reflectance as the sensor sees it is the scene's times it (a lidar preset's [extensions.surface])
BeamSignal traceBeamSignal(const Ray& ray, double wavelength_nm, double range_max_m, const PhysicalParams& p,
                           const Scene& scene, const SurfaceSet& surfaces, const SmokeField& field,
                           SurfaceHit* central_hit, BeamSmoke* central_smoke,
                           const std::vector<double>* reflectance_factor = nullptr);
/// @brief The same into `out`, whose storage is reused (a frame's beams, one after another).
void traceBeamSignalInto(BeamSignal& out, const Ray& ray, double wavelength_nm, double range_max_m,
                         const PhysicalParams& p, const Scene& scene, const SurfaceSet& surfaces,
                         const SmokeField& field, SurfaceHit* central_hit, BeamSmoke* central_smoke,
                         const std::vector<double>* reflectance_factor);

/// @brief URG-04LX: amplitude and phase of the summed echoes at two modulation frequencies.
/// Codes: 18 strong reflection (amplitude above saturation), 1 low intensity, 8 intensity
/// difference of the two waves (a spread return), 0 nothing in range.
BeamResult amcwBeam(const LrfSpec& spec, const PhysicalParams& p, const BeamSignal& s, KeyedRng& rng);

/// @brief URG-04LX without receiver or datasheet noise: the reading the summed echoes give.
BeamResult amcwBeamExpected(const LrfSpec& spec, const PhysicalParams& p, const BeamSignal& s);

/// Noise-free amplitudes |Σ P·e^{i·k·r}| of the summed echoes at the two modulation frequencies.
struct AmcwAmplitudes {
    double lo = 0, hi = 0;
};

/// @brief URG-04LX without receiver noise: the amplitudes amcwBeam's validity rules look at.
AmcwAmplitudes amcwAmplitudes(const PhysicalParams& p, const BeamSignal& s);

/// @brief Probability that amcwBeam returns an error code for noise-free amplitudes A, in the
/// high-SNR limit where each measured amplitude is Gaussian about its Rician mean √(A² + σ²) with
/// σ = noise_floor: 1 − P(snr_min·σ ≤ X ≤ saturation_power, |Y − X| ≤ two_wave_tolerance·X),
/// X, Y the coarse and fine amplitudes. Smooth in every parameter (for fitting the noise floor).
double amcwErrorProbability(const PhysicalParams& p, const AmcwAmplitudes& A);

/// @brief The same for a beam's signal, with the noise-free phase range leaving the sensor's
/// window counted as an error.
double amcwErrorProbability(const LrfSpec& spec, const PhysicalParams& p, const BeamSignal& s);

/// @brief The standard deviation of a valid amcwBeam reading [m]: the fine phasor's phase noise
/// σ/A_hi over its wavenumber, and the datasheet noise at the range, in quadrature.
double amcwRangeSigma(const LrfSpec& spec, const PhysicalParams& p, const BeamSignal& s);

/// @brief The transmitted pulse's σ in range [m]: its FWHM in time, over the two ways, as a Gaussian's σ.
double pulseSigma_m(const PhysicalParams& p);

/// A beam's received waveform: Gaussian pulses (the transmitted pulse's shape) at each echo's
/// range, sampled every dr [m] from lo [m]; empty when no echo lies within range.
struct Waveform {
    double lo = 0, dr = 0;
    double sig_p = 0;  ///< pulse σ in range [m]
    std::vector<double> w;  ///< normalised power per sample
};

/// @brief The noise-free waveform of a beam's echoes up to range_max_m (and the pulse's reach
/// beyond), `samples_per_sigma` samples per pulse σ: noise alone stays below a detection threshold
/// of 6 σ (probability ~1e-9 a sample).
Waveform pulsedWaveform(double range_max_m, const PhysicalParams& p, const BeamSignal& s, int samples_per_sigma = 4);
/// @brief The same into `out`, whose storage is reused (a frame's beams, one after another).
void pulsedWaveform(double range_max_m, const PhysicalParams& p, const BeamSignal& s, int samples_per_sigma,
                    Waveform& out);

/// One echo found in a waveform: a run of samples at or above the detection threshold.
struct WaveformEcho {
    double peak = 0;  ///< its largest sample (normalised power)
    double peak_m = 0;  ///< where it peaks [m]
    double lead_m = 0, trail_m = 0;  ///< its half-maximum crossings [m]
};

/// @brief The echoes of a waveform in order of range, at most `max_echoes`: each run of samples
/// at or above `threshold`, its peak and the half-maximum crossings around the peak.
std::vector<WaveformEcho> waveformEchoes(const Waveform& f, double threshold, int max_echoes);
/// @brief The echo peaking at sample kp of waveform f over `pedestal`: its half-height crossings
/// (half-way from the pedestal to the peak, linear between samples), the leading one searched no
/// earlier than sample `from`, the trailing one no later than sample `to`.
WaveformEcho waveformPeakAt(const Waveform& f, int kp, double pedestal, int from, int to);

/// @brief LMS200: the waveform (Gaussian pulse ⊗ echoes + noise), first echo above threshold,
/// range at its half-maximum leading edge plus half the pulse width. Codes: 8183 no echo,
/// 8189 echo too weak or too wide (ambiguous), 8191 dazzled.
BeamResult pulsedBeam(const LrfSpec& spec, const PhysicalParams& p, const BeamSignal& s, KeyedRng& rng);

/// @brief LMS200 without receiver noise: the reading the noise-free waveform gives (range or
/// error value), what a fit of the Sick's thresholds compares recorded readings with.
BeamResult pulsedBeamExpected(const LrfSpec& spec, const PhysicalParams& p, const BeamSignal& s);

/// @brief Probability that pulsedBeam returns an error value, estimated from `draws` noisy
/// readings of the beam's waveform with fixed random numbers (common to every call: the same
/// signal always gives the same estimate, and nearby signals are compared on the same noise).
/// Standard error ≤ 0.5/√draws. The peak of a noisy waveform is the largest of several noisy samples and the
/// noise widens the echo, so no simple closed form holds (tests/test_beam_model.cpp).
double pulsedErrorProbability(const LrfSpec& spec, const PhysicalParams& p, const BeamSignal& s, int draws = 1024);

}  // namespace smokescan
