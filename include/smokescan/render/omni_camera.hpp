#pragma once
/// @file omni_camera.hpp
/// @brief A single-viewpoint catadioptric camera: a camera looking up into a paraboloidal mirror
/// (Nayar), as in the omnicam paper (Nguyen and Visser; docs/omnicam.md).
///
/// A ray leaving the viewpoint at incidence θ from straight down (the mirror's axis, local −z)
/// and azimuth φ (from local +x towards local +y) meets the mirror at distance R/(1 + cos θ) from
/// its focus and lands at image radius ρ = R·sin θ/(1 + cos θ) = R·tan(θ/2), so θ = 2·arctan(ρ/R);
/// R is the radius of the 90° (horizon) circle. The image shows the world as a map seen from
/// above: local +x to the right of the centre, local +y up.
///
/// | parameter         | default | unit | meaning                                                  |
/// |-------------------|---------|------|----------------------------------------------------------|
/// | width, height     | 1024, 768 | px | the paper's image                                        |
/// | cx, cy            | centre  | px   | the image of the mirror's axis                           |
/// | mirror_radius     | 192     | px   | R, the 90° circle (the paper's 192 px at 1024×768)        |
/// | max_incidence_deg | 110     | deg  | the mirror's rim: no ray beyond it                       |
/// | base_radius       | 0       | px   | the robot's base hides the image within this radius      |
#include "smokescan/render/camera.hpp"

namespace smokescan {

struct OmniIntrinsics {
    int width = 1024, height = 768;
    double cx = 512, cy = 384;
    double mirror_radius = 192;
    double max_incidence_deg = 110;
    double base_radius = 0;
};

class OmniCamera final : public CameraModel {
public:
    /// @throw Error (naming `name`) for a non-positive size or mirror radius, a rim at or beyond
    /// 170°, or a base that hides the whole mirror.
    OmniCamera(const Pose& pose, const OmniIntrinsics& k, const std::string& name = "omni");
    int width() const override { return k_.width; }
    int height() const override { return k_.height; }
    /// False outside the mirror's rim and on the base.
    bool generateRay(double x_px, double y_px, Ray& ray) const override;

    /// @brief Incidence θ [rad] from straight down at image radius rho_px: 2·arctan(ρ/R).
    double incidence(double rho_px) const;
    /// @brief Image radius [px] of incidence theta_rad: R·tan(θ/2).
    double radius(double theta_rad) const;
    /// @brief The image point of a world point (any point but the viewpoint), in pixels
    /// (continuous: pixel (i, j) covers [i, i+1) × [j, j+1)).
    Vec2 project(const Vec3& world) const;
    /// @brief Distance [m] along the floor from the point below the viewpoint to the floor point
    /// seen at image radius rho_px, for a viewpoint height_m above the floor: h·tan θ, or +∞ at or
    /// above the horizon.
    double floorDistance(double rho_px, double height_m) const;
    const OmniIntrinsics& intrinsics() const { return k_; }
    const Pose& pose() const { return pose_; }

private:
    Pose pose_;
    OmniIntrinsics k_;
    double rim_radius_ = 0;  ///< image radius of the rim [px]
};

}  // namespace smokescan
