#include "smokescan/render/camera.hpp"

#include <cmath>

#include "smokescan/core/error.hpp"
#include "smokescan/render/omni_camera.hpp"
#include "smokescan/scene/scene.hpp"

namespace smokescan {

PinholeIntrinsics PinholeIntrinsics::fromHfov(int w, int h, double hfov_deg)
{
    PinholeIntrinsics k;
    k.width = w;
    k.height = h;
    k.fx = k.fy = 0.5 * w / std::tan(0.5 * hfov_deg * M_PI / 180.0);
    k.cx = 0.5 * w;
    k.cy = 0.5 * h;
    return k;
}

PinholeCamera::PinholeCamera(const Pose& pose, const PinholeIntrinsics& k) : pose_(pose), k_(k) {}

bool PinholeCamera::generateRay(double x, double y, Ray& ray) const
{
    const Vec3 local(1.0, (k_.cx - x) / k_.fx, (k_.cy - y) / k_.fy);
    ray.o = pose_.t;
    ray.d = pose_.rotate(local).normalized();
    return true;
}

std::unique_ptr<CameraModel> makeCamera(const Camera& cam)
{
    if (!cam.pose.t.allFinite() || !cam.pose.R.allFinite()) throw Error(cam.name, "camera pose is not finite");
    if (cam.width <= 0 || cam.height <= 0) throw Error(cam.name, "camera resolution must be > 0");
    if (cam.kind == CameraKind::Omni) {
        OmniIntrinsics k;
        k.width = cam.width;
        k.height = cam.height;
        k.cx = cam.cx_px >= 0 ? cam.cx_px : 0.5 * cam.width;
        k.cy = cam.cy_px >= 0 ? cam.cy_px : 0.5 * cam.height;
        k.mirror_radius = cam.mirror_radius_px;
        k.max_incidence_deg = cam.max_incidence_deg;
        k.base_radius = cam.base_radius_px;
        return std::make_unique<OmniCamera>(cam.pose, k, cam.name);
    }
    return std::make_unique<PinholeCamera>(cam.pose, pinholeIntrinsics(cam));
}

PinholeIntrinsics pinholeIntrinsics(const Camera& cam)
{
    PinholeIntrinsics k = PinholeIntrinsics::fromHfov(cam.width, cam.height, cam.hfov_deg);
    if (cam.fx_px > 0) k.fx = cam.fx_px;
    if (cam.fy_px > 0)
        k.fy = cam.fy_px;
    else if (cam.fx_px > 0)
        k.fy = cam.fx_px;
    if (cam.cx_px >= 0) k.cx = cam.cx_px;
    if (cam.cy_px >= 0) k.cy = cam.cy_px;
    if (!(k.fx > 0) || !(k.fy > 0) || !std::isfinite(k.fx) || !std::isfinite(k.fy))
        throw Error(cam.name, "camera focal length must be finite and > 0");
    return k;
}

bool inView(const Camera& cam, const Vec3& direction)
{
    if (cam.kind == CameraKind::Omni) return true;  // all round, below its mirror's rim
    const Vec3 d = cam.pose.R.transpose() * direction;  // +x forward, +y image left, +z up
    if (!(d.x() > 0)) return false;
    const PinholeIntrinsics k = pinholeIntrinsics(cam);
    const double u = k.cx - k.fx * d.y() / d.x(), v = k.cy - k.fy * d.z() / d.x();
    return u >= 0 && u <= k.width && v >= 0 && v <= k.height;
}

}  // namespace smokescan
