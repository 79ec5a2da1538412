#pragma once
/// @file physical_params.hpp
/// @brief Parameters of the physical laser return model (docs/sensors.md, "Physical model").
///
/// Received powers are normalised: 1 is the return of a white Lambertian target (ρ = 1) at 1 m,
/// at normal incidence, in clear air, at full overlap. So P = π·f_r·cos θ·O(R)/R²·T²(R) for a
/// surface (the lidar equation of Rasshofer et al. 2011 with C_A·P₀ = 1) and
/// dP = π·β(r)·O(r)/r²·T²(r) dr for smoke.
///
/// | parameter           | URG-04LX   | LMS200   | unit | source / meaning                                          |
/// |---------------------|------------|----------|------|-----------------------------------------------------------|
/// | divergence_mrad     | 10         | 12       | mrad | full beam divergence; URG: footprint < 20 mm at 2 m (datasheet); Sick: assumed |
/// | sub_rays            | 5          | 5        | –    | rays over the footprint (centre + 4 at 0.7 of the half-angle) |
/// | window_m            | 0.02       | 0.02     | m    | no return from inside the housing                          |
/// | overlap_start_m     | 1.5        | 0.1      | m    | start of the biaxial overlap (URG: calibrated, see below; Sick: assumed) |
/// | overlap_full_m      | 3.0        | 1.5      | m    | full overlap; O rises as a smoothstep in between           |
/// | overlap_floor       | 0.03       | 0.01     | –    | defocused light below the overlap, itself falling as r² (assumed) |
/// | overlap_blur_m      | 0          | 0        | m    | the floor falls as r² nearer than this; 0 = overlap_start_m (assumed) |
/// | noise_floor         | 1.728e-4   | 5e-5     | –    | r.m.s. receiver noise (normalised power), calibrated       |
/// | saturation_power    | 40         | 40       | –    | received power that dazzles (URG code 18, Sick 8191), assumed |
/// | snr_min             | 25         | –        | –    | AMCW: amplitude/noise below which the step is invalid (code 1), calibrated with noise_floor |
/// | mod_freq_lo_hz      | 6.8e6      | –        | Hz   | AMCW coarse frequency: unambiguous to 22 m (cf. code 0 "possibly at 22 m"), assumed |
/// | mod_freq_hi_hz      | 46.5e6     | –        | Hz   | AMCW fine frequency (ambiguity 3.2 m), assumed              |
/// | two_wave_tolerance  | 0.15       | –        | –    | AMCW: relative amplitude difference of the two waves allowed (code 8), calibrated |
/// | pulse_fwhm_ns       | –          | 4        | ns   | Sick pulse width (assumed)                                 |
/// | threshold_snr       | –          | 6        | –    | Sick: echo detection threshold over the noise              |
/// | valid_snr           | –          | 12       | –    | Sick: an echo peaking below this is too weak (8189)        |
/// | max_echo_width      | –          | 4        | –    | Sick: an echo wider (FWHM) than this × the pulse's is smoke dispersed over metres: ambiguous (8189), assumed |
///
/// Range noise follows the received power: the receiver noise enters the phasors (AMCW) and the
/// waveform (pulsed), so the phase or leading-edge jitter grows as noise_floor/amplitude
/// (σ_r ≈ c/(4π f_hi)·noise/A for the URG); the datasheet σ (lrf.hpp) is added on top as the
/// strong-signal floor.
///
/// "assumed" values are engineering guesses, documented as such; "calibrated" ones are fitted
/// so that the bocas scene reproduces the smoke paper (docs/sensors.md).
#include "smokescan/sensor_config/sensor_kind.hpp"

namespace smokescan {

struct PhysicalParams {
    double divergence_mrad = 10.0;
    int sub_rays = 5;
    double overlap_start_m = 0.1;
    double overlap_full_m = 1.5;
    double overlap_floor = 0.01;
    double overlap_blur_m = 0;  ///< the floor falls as r² nearer than this [m]; 0 = overlap_start_m
    double window_m = 0.02;
    double noise_floor = 5e-5;
    double saturation_power = 40.0;
    // AMCW (URG-04LX)
    double snr_min = 8.0;
    double mod_freq_lo_hz = 6.8e6;
    double mod_freq_hi_hz = 46.5e6;
    double two_wave_tolerance = 0.15;
    // pulsed (LMS200)
    double pulse_fwhm_ns = 4.0;
    double threshold_snr = 6.0;
    double valid_snr = 12.0;
    double max_echo_width = 4.0;
    /// Smoke along a beam is summed into echoes this long [m]: for the URG-04LX and LMS200 0.1 m,
    /// 0.2 rad of the fine AMCW phase (sinc loss 0.2 %) and 0.4 of the Sick pulse's σ.
    double smoke_bin_m = 0.1;
    /// When > 0, the smoke's backscatter along the central ray is summed onto points this far
    /// apart (BeamSignal::smoke_cells) instead of echoes [m]: the 3D lidars set it to half their
    /// waveform's sample spacing, and the smoke goes onto the waveform by one fixed kernel.
    double smoke_cell_m = 0;

    /// Overlap O(r) ∈ [0, 1] of the receiver's field of view with the beam at range r [m].
    double overlap(double r_m) const;
    /// The range from which O(r) no longer changes [m]: O(r) = O(this) for every r beyond it.
    double overlapSettled_m() const;
};

/// @brief Defaults for a sensor type, calibrated values included.
PhysicalParams physicalDefaults(SensorType type);

}  // namespace smokescan
