#pragma once
/// @file saturation_curve.hpp
/// @brief The density ↔ saturation curve (the smoke paper's Fig. 7), derived from what the camera
/// sees, and its fit with Ceres (docs/calibration.md has the derivation).
///
/// A target of linear channel radiances L_c seen through a path of grey smoke with transmittance
/// T = e^{−bρ} and airlight A (Koschmieder: L_c' = L_c·T + A·(1 − T)) has linear HSV saturation
///     S_lin(ρ) = S0 / (1 + a·(e^{bρ} − 1)),
/// and a display encoding e = L^γ (sRGB ≈ γ = 1/2.2) turns it into the measured saturation
///     S(ρ) = 1 − (1 − S_lin(ρ))^γ   (exposure cancels: only the ratio min/max enters).
///
/// | parameter | meaning                                             | unit        |
/// |-----------|-----------------------------------------------------|-------------|
/// | S0        | clear-air linear saturation of the target            | –           |
/// | a         | airlight ratio A / L_max (airlight over the target's brightest channel) | – |
/// | b         | optical path per unit density: σ_t per unit density × camera–target distance | 1/density |
/// | gamma     | display encoding exponent (fixed, 1/2.2)             | –           |
/// | floor     | the camera's noise floor f: S_measured = √(S² + f²) (fixed, from the camera model) | – |
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace smokescan {

struct SaturationCurve {
    double S0 = 0.5, a = 1.0, b = 100.0;
    double gamma = 1.0 / 2.2;
    /// The camera's noise floor f (derived from its sensor, not fitted; 0: a noiseless camera):
    /// the measured saturation is √(S(ρ)² + f²), which a grey pixel's noise alone gives.
    double floor = 0.0;

    double operator()(double rho) const;
    /// @brief Density at which the curve reads saturation S. @throw Error when S is not reached
    /// (at or above the clear-air value, or at or below 0).
    double invert(double S) const;
};

/// One calibration point: saturation measured at a density, with its standard error.
struct SaturationPoint {
    double density = 0;
    double saturation = 0;
    double sigma = 0.01;  ///< standard error of the saturation (> 0)
};

/// | field                    | default | meaning                                                    |
/// |--------------------------|---------|------------------------------------------------------------|
/// | loss                     | huber   | RobustLoss: none, huber, cauchy (scale in units of σ)      |
/// | loss_scale               | 2.0     | residual (in σ) where the robust loss departs from least squares |
/// | scale_covariance_by_chi2 | true    | multiply the covariance by χ²/dof when that exceeds 1 (σ's underestimated) |
/// | gamma                    | 1/2.2   | display encoding exponent                                   |
/// The robust loss of the curve fit.
enum class RobustLoss { None, Huber, Cauchy };

struct CurveFitConfig {
    RobustLoss loss = RobustLoss::Huber;
    double loss_scale = 2.0;
    bool scale_covariance_by_chi2 = true;
    double gamma = 1.0 / 2.2;
    double floor = 0.0;  ///< the camera's noise floor, fixed (SaturationCurve::floor)
};

struct CurveFitResult {
    SaturationCurve curve;
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  ///< of (S0, a, b)
    std::array<double, 3> std_error{{0, 0, 0}};
    bool converged = false;
    double chi2 = 0;  ///< Σ ((S_i − S(ρ_i))/σ_i)²
    int dof = 0;  ///< points − 3
    double r2 = 0;  ///< coefficient of determination
    std::string message;  ///< Ceres' summary line

    /// Density at saturation S with its standard error (delta method: the curve's covariance
    /// and, if given, the standard error sigma_S of S itself).
    std::pair<double, double> invert(double S, double sigma_S = 0.0) const;
};

/// @brief Fits the curve to the points with Ceres (robust loss, bounds S0 ∈ (0, 1], a, b > 0),
/// then the covariance with ceres::Covariance.
/// @throw Error for degenerate data: fewer than 4 distinct densities, saturations that do not
/// change, non-finite values, negative densities, saturations outside [0, 1], σ ≤ 0.
CurveFitResult fitSaturationCurve(const std::vector<SaturationPoint>& points, const CurveFitConfig& cfg = {});

}  // namespace smokescan
