#pragma once
/// @file colour_mix_curve.hpp
/// @brief The saturation curve from the colours that mix in each pixel (docs/calibration.md).
/// A patch of linear colour l_c seen through smoke of transmittance T = e^{−bρ} adds scattered
/// light of colour A_c(ρ): x_c = l_c·T + A_c(ρ)·(1 − T). The scattered light is not grey (the
/// room's walls are warm), so saturation does not fall to 0: a blue patch passes through grey where
/// the warm light cancels its blue and then takes the light's own colour. Nor is it one colour:
/// in thin smoke it is the room's light scattered once (warm), in dense smoke the smoke's own
/// multiply scattered glow (brighter and greyer: measured in converged renders, light_mixing.hpp).
/// The drifting-light fit lets A(ρ) = w·A_thin + (1 − w)·A_dense with w = e^{−κρ}: it describes the
/// points, but b, κ and the two lights trade off, so only its threshold is meant (docs/calibration.md).
/// Encoded by the camera
/// (y = x^γ) its saturation is 1 − min_c y_c / max_c y_c. Two measured, not fitted, inputs make it
/// the camera's mean over the patch: the camera's noise on each channel (relative sd f·√π/3, with
/// f the saturation it gives a grey pixel at the patch's exposed level: develop.hpp
/// greyNoiseSaturation, per density), taken as 1 − E[min]/E[max] with Clark's moments of the
/// maximum of normals, and the patch's pixel
/// brightness classes in clear air (the lamp lights it unevenly, and a glossy patch has a
/// highlight), over which the mean is taken.
///
/// | parameter | meaning                                                          | unit      |
/// |-----------|------------------------------------------------------------------|-----------|
/// | b         | extinction per unit density × the effective optical path          | 1/density |
/// | A_G, A_B  | thin smoke's scattered light, green and blue relative to its red (A_R = 1) | – |
/// | A_dense   | dense smoke's scattered light (R, G, B), on the same scale        | –         |
/// | κ         | how fast the light turns from thin to dense, per unit density     | 1/density |
/// | l_p       | patch p's clear-air linear colour (R, G, B), relative to A_R      | –         |
/// | gamma     | display encoding exponent (fixed, 1/2.2)                          | –         |
#include <array>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "smokescan/calib/saturation_curve.hpp"

namespace smokescan {

struct ColourMixCurve {
    double b = 300;
    std::array<double, 3> airlight{{1.0, 1.0, 1.0}};  ///< thin smoke's scattered light (R = 1)
    std::array<double, 3> airlight_dense{{1.0, 1.0, 1.0}};  ///< dense smoke's, on the same scale
    double kappa = 0;  ///< the light's change from one to the other per unit density (0: none)
    std::vector<std::string> names;  ///< patches
    std::vector<std::array<double, 3>> target;  ///< l_p
    std::vector<double> weight;  ///< each patch's share of the target's pixels (the combined curve)
    std::vector<double> floor_density;  ///< where the noise floor was measured
    std::vector<std::vector<double>> floor;  ///< [patch][density]: f
    std::vector<std::vector<double>>
        brightness;  ///< [patch]: pixel brightness classes (luminance / patch mean, clear air)
    double gamma = 1.0 / 2.2;

    /// Patch p's noise-free saturation at density rho.
    double clean(size_t p, double rho) const;
    /// The noise floor of patch p at rho (linear between the measured densities, held beyond).
    double floorAt(size_t p, double rho) const;
    /// Patch p's measured saturation at rho.
    double patch(size_t p, double rho) const;
    /// The whole target's: the patches' pixel-weighted mean.
    double combined(double rho) const;
    /// The scattered light's colour at rho: e^{−κρ}·airlight + (1 − e^{−κρ})·airlight_dense.
    std::array<double, 3> airlightAt(double rho) const;
    /// (A0_G, A0_B, s, Ainf_G/s, Ainf_B/s, kappa): the fit's airlight parameters.
    std::array<double, 6> packedAirlight() const;
};

/// One patch's points and noise floors (floor[i] at points[i]'s density), and its pixel share.
struct PatchPoints {
    std::string name;
    double weight = 1;
    std::vector<SaturationPoint> points;
    std::vector<double> floor;
    std::array<double, 3> clear_colour{{1, 1, 1}};  ///< a start for l_p (any scale)
    std::vector<double> brightness;  ///< pixel brightness classes in clear air (empty: one class, 1)
};

struct ColourMixFit {
    ColourMixCurve curve;
    /// Of (b, A_G, A_B, s, A_dense,G/s, A_dense,B/s, κ, l_1 (3), l_2 (3), …), s = A_dense,R.
    Eigen::MatrixXd covariance;
    std::vector<double> std_error;
    double chi2 = 0;
    int dof = 0;
    std::vector<double> patch_chi2;
    bool converged = false;
    std::string message;

    /// @brief Density at which the combined curve reads S, with its delta-method standard error.
    /// @throw Error when the curve does not reach S within [0, rho_max].
    std::pair<double, double> invert(double S, double rho_max) const;
};

/// @brief Fits b, the scattered light's two colours and κ, and every patch's colour to all patches' points at once
/// with Ceres (one extinction for all), and the covariance with ceres::Covariance. With one patch
/// it is that patch's own fit. @throw Error for fewer than 6 points per patch, no more points than
/// parameters (3 + 3 per patch, 4 more with the drift), or bad values.
/// `drifting_light`: also fit the scattered light's drift (A_dense, κ); else κ = 0, one colour.
/// `held_light`: the scattered light (both colours and κ) held at that curve's, not fitted: only b
/// and the patches' colours are free (a patch's own extinction under the light the joint fit measured).
ColourMixFit fitColourMix(const std::vector<PatchPoints>& patches, double gamma = 1.0 / 2.2,
                          bool drifting_light = false, const ColourMixCurve* held_light = nullptr);

/// Each patch's own extinction under one scattered light, and whether they agree.
struct PatchExtinctions {
    std::map<std::string, ColourMixFit> fits;  ///< per patch: b and its colour free, the light held
    double b_mean = 0;  ///< the b's weighted mean (inverse variances)
    double chi2 = 0;  ///< Σ ((b_p − b_mean) / se_p)²
    int dof = 0;  ///< patches fitted − 1 (0: no comparison)
    double p_value = 1;  ///< P(χ²_dof > chi2)
};

/// @brief Fits each patch alone with the scattered light held at `light`'s (thin and dense colours
/// and κ: the room's and the smoke's, not the patch's) and compares their b's. Each b's error leaves
/// out the light's, which is common to every patch. Patches whose fit fails are left out.
PatchExtinctions fitPatchesUnderLight(const std::vector<PatchPoints>& patches, double gamma,
                                      const ColourMixCurve& light);

}  // namespace smokescan
