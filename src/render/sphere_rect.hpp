#pragma once
// Internal: uniform sampling of the solid angle a rectangle subtends from a point (Ureña, Fajardo,
// King 2013, "An Area-Preserving Parametrization for Spherical Rectangles"). The estimator's
// weight is then the solid angle itself — bounded by 2π — where sampling the rectangle's area
// gives area·cos/d², whose variance is infinite for scattering points close to the light.
#include <algorithm>
#include <cmath>

#include "smokescan/core/ray.hpp"

namespace smokescan {

class SphericalRectangle {
public:
    /// Rectangle: corner s, edges ex, ey (orthogonal); seen from o.
    SphericalRectangle(const Vec3& o, const Vec3& s, const Vec3& ex, const Vec3& ey) : o_(o)
    {
        const double exl = ex.norm(), eyl = ey.norm();
        x_ = ex / exl;
        y_ = ey / eyl;
        z_ = x_.cross(y_);
        const Vec3 d = s - o;
        z0_ = d.dot(z_);
        if (z0_ > 0) {
            z_ = -z_;
            z0_ = -z0_;
        }
        x0_ = d.dot(x_);
        y0_ = d.dot(y_);
        x1_ = x0_ + exl;
        y1_ = y0_ + eyl;
        const Vec3 v00(x0_, y0_, z0_), v01(x0_, y1_, z0_), v10(x1_, y0_, z0_), v11(x1_, y1_, z0_);
        const Vec3 n0 = v00.cross(v10).normalized(), n1 = v10.cross(v11).normalized(), n2 = v11.cross(v01).normalized(),
                   n3 = v01.cross(v00).normalized();
        auto ang = [](double c) { return std::acos(std::clamp(c, -1.0, 1.0)); };
        const double g0 = ang(-n0.dot(n1)), g1 = ang(-n1.dot(n2)), g2 = ang(-n2.dot(n3)), g3 = ang(-n3.dot(n0));
        b0_ = n0.z();
        b1_ = n2.z();
        k_ = 2 * M_PI - g2 - g3;
        S_ = g0 + g1 - k_;
    }
    /// Solid angle [sr]; sampling is reliable only when it is not tiny and the point is off the plane.
    double solidAngle() const { return S_; }
    bool usable() const { return S_ > 1e-6 && z0_ < -1e-9 && std::isfinite(S_); }

    /// A point on the rectangle, uniformly distributed in solid angle.
    Vec3 sample(double u, double v) const
    {
        const double au = u * S_ + k_;
        const double fu = (std::cos(au) * b0_ - b1_) / std::sin(au);
        double cu = (fu > 0 ? 1.0 : -1.0) / std::sqrt(fu * fu + b0_ * b0_);
        cu = std::clamp(cu, -1.0, 1.0);
        double xu = -(cu * z0_) / std::sqrt(std::max(1e-300, 1 - cu * cu));
        xu = std::clamp(xu, x0_, x1_);
        const double d = std::sqrt(xu * xu + z0_ * z0_);
        const double h0 = y0_ / std::sqrt(d * d + y0_ * y0_), h1 = y1_ / std::sqrt(d * d + y1_ * y1_);
        const double hv = h0 + v * (h1 - h0), hv2 = hv * hv;
        const double yv = hv2 < 1 - 1e-12 ? (hv * d) / std::sqrt(1 - hv2) : y1_;
        return o_ + xu * x_ + yv * y_ + z0_ * z_;
    }

private:
    Vec3 o_, x_, y_, z_;
    double x0_ = 0, y0_ = 0, x1_ = 0, y1_ = 0, z0_ = 0, b0_ = 0, b1_ = 0, k_ = 0, S_ = 0;
};

}  // namespace smokescan
