#include "smokescan/core/ray.hpp"

#include <algorithm>
#include <cmath>

namespace smokescan {

Pose Pose::fromRpyDeg(const Vec3& position_m, const Vec3& rpy_deg)
{
    const Vec3 r = rpy_deg * (M_PI / 180.0);
    Pose p;
    p.R = (Eigen::AngleAxisd(r.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(r.y(), Vec3::UnitY()) *
           Eigen::AngleAxisd(r.x(), Vec3::UnitX()))
              .toRotationMatrix();
    p.t = position_m;
    return p;
}

bool Aabb::clip(const Ray& r, double& t0, double& t1) const { return clip(r, inverseDirection(r), t0, t1); }

Vec3 Aabb::inverseDirection(const Ray& r)
{
    Vec3 inv;
    for (int a = 0; a < 3; ++a) inv[a] = r.d[a] == 0.0 ? 0.0 : 1.0 / r.d[a];
    return inv;
}

bool Aabb::clip(const Ray& r, const Vec3& inv_d, double& t0, double& t1) const
{
    if (empty()) return false;
    for (int a = 0; a < 3; ++a) {
        if (r.d[a] == 0.0) {
            if (r.o[a] < lo[a] || r.o[a] > hi[a]) return false;
            continue;
        }
        double ta = (lo[a] - r.o[a]) * inv_d[a], tb = (hi[a] - r.o[a]) * inv_d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 <= t1;
}

}  // namespace smokescan
