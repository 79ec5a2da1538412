#include "smokescan/render/omni_camera.hpp"

#include <cmath>

#include "smokescan/core/error.hpp"

namespace smokescan {

OmniCamera::OmniCamera(const Pose& pose, const OmniIntrinsics& k, const std::string& name) : pose_(pose), k_(k)
{
    if (!pose.t.allFinite() || !pose.R.allFinite()) throw Error(name, "camera pose is not finite");
    if (k.width <= 0 || k.height <= 0) throw Error(name, "camera resolution must be > 0");
    if (!(k.mirror_radius > 0) || !std::isfinite(k.mirror_radius))
        throw Error(name, "mirror_radius_px must be finite and > 0");
    if (!(k.max_incidence_deg > 0) || !(k.max_incidence_deg < 170))
        throw Error(name, "max_incidence_deg must lie in (0, 170)");
    if (!std::isfinite(k.cx) || !std::isfinite(k.cy)) throw Error(name, "image centre must be finite");
    rim_radius_ = radius(k.max_incidence_deg * M_PI / 180);
    if (!(k.base_radius >= 0) || k.base_radius >= rim_radius_)
        throw Error(name, "base_radius_px hides the whole mirror");
}

double OmniCamera::incidence(double rho_px) const { return 2 * std::atan(rho_px / k_.mirror_radius); }

double OmniCamera::radius(double theta_rad) const { return k_.mirror_radius * std::tan(0.5 * theta_rad); }

bool OmniCamera::generateRay(double x_px, double y_px, Ray& ray) const
{
    const double dx = x_px - k_.cx, dy = k_.cy - y_px;  // image up = local +y
    const double rho = std::hypot(dx, dy);
    if (rho > rim_radius_ || rho < k_.base_radius) return false;
    const double theta = incidence(rho), phi = std::atan2(dy, dx);
    const Vec3 local(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), -std::cos(theta));
    ray.o = pose_.t;
    ray.d = pose_.rotate(local).normalized();
    return true;
}

Vec2 OmniCamera::project(const Vec3& world) const
{
    const Vec3 q = pose_.R.transpose() * (world - pose_.t);
    const double theta = std::atan2(std::hypot(q.x(), q.y()), -q.z());
    const double rho = radius(theta), phi = std::atan2(q.y(), q.x());
    return Vec2(k_.cx + rho * std::cos(phi), k_.cy - rho * std::sin(phi));
}

double OmniCamera::floorDistance(double rho_px, double height_m) const
{
    const double theta = incidence(rho_px);
    return theta >= 0.5 * M_PI ? kInf : height_m * std::tan(theta);
}

}  // namespace smokescan
