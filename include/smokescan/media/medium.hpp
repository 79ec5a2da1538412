#pragma once
/// @file medium.hpp
/// @brief Optical properties of a smoke per unit of grid density.
///
/// | parameter        | default | unit                   | meaning                                      |
/// |------------------|---------|------------------------|----------------------------------------------|
/// | sigma_t_550      | 200     | 1/m per density unit   | extinction at 550 nm (camera, visible)       |
/// | sigma_t_785      | 200     | 1/m per density unit   | extinction at 785 nm (Hokuyo URG-04LX)       |
/// | sigma_t_905      | 200     | 1/m per density unit   | extinction at 905 nm (Sick LMS200)           |
/// | albedo           | 0.97    | –                      | single-scattering albedo σ_s/σ_t             |
/// | g                | 0.7     | –                      | Henyey–Greenstein asymmetry                  |
/// | lidar_ratio_sr   | 0       | sr                     | extinction-to-backscatter ratio σ_t/β; 0 = from HG |
///
/// The density unit is the smoke paper's engine density (its threshold 0.0028 at saturation 0.14),
/// so the paper's penetration power (density·m) is the column ∫ρ ds the integrator returns. The
/// default extinction, 200 /m per unit (kCalibratedSigmaT), is calibrated: with it the rendered
/// BOCAS target reaches HSV saturation 0.14 at density 0.0028 (`smokescan calibrate bocas`,
/// calib/bocas.json; docs/calibration.md). Defaults describe theatrical oil/glycol fog, the BOCAS
/// smoke: droplets near 1 µm give an Ångström exponent near 0 (same σ_t at all three wavelengths)
/// and albedo close to 1. Presets for soot (Å ≈ 1, albedo 0.3) and fine smoke (Å ≈ 2, albedo 0.9)
/// follow typical aerosol values (docs/smoke.md, docs/references.md).
///
/// Backscatter for the lidar equation, β = σ_s·p(π) [1/(m·sr)]: HG's p(π) = (1−g)/(4π(1+g)²) is
/// known to understate the backscatter peak of real droplets and soot (HG has no glory), so a
/// medium may state its lidar ratio S = σ_t/β instead, the quantity aerosol lidars measure.
#include <string>

namespace smokescan {

struct Medium {
    /// Extinction per unit of engine density at 550 nm that puts the BOCAS target's saturation 0.14
    /// at density 0.0028 [1/m] (calib/bocas.json).
    static constexpr double kCalibratedSigmaT = 200.0;

    std::string name = "theatrical_fog";
    double sigma_t_550 = kCalibratedSigmaT;
    double sigma_t_785 = kCalibratedSigmaT;
    double sigma_t_905 = kCalibratedSigmaT;
    double albedo = 0.97;
    double g = 0.7;
    double lidar_ratio_sr = 0;

    /// Backscatter per unit extinction, β/σ_t [1/sr]: 1/S, or albedo·p_HG(π) when S is 0.
    double backscatterPerExtinction() const;

    /// σ_t per unit density [1/m] at a wavelength: the tabulated value at 550/785/905 nm,
    /// power-law (Ångström) interpolation between them, extrapolation beyond.
    double sigmaT(double wavelength_nm) const;

    /// A named preset: "theatrical_fog", "soot", "fine_smoke". Throws Error on an unknown name.
    static Medium preset(const std::string& name);
    /// σ_t(λ) = sigma_t_550 · (λ/550)^(−angstrom).
    static Medium fromAngstrom(const std::string& name, double sigma_t_550, double angstrom, double albedo, double g);
};

}  // namespace smokescan
