#pragma once
/// @file ray.hpp
/// @brief World-space rays and the small geometric types every module shares. Units: metres.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <limits>

namespace smokescan {

using Vec3 = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;
constexpr double kInf = std::numeric_limits<double>::infinity();

/// A ray o + t·d with |d| = 1, so that t is a distance in metres.
struct Ray {
    Vec3 o = Vec3::Zero();
    Vec3 d = Vec3::UnitX();
    Vec3 at(double t_m) const { return o + t_m * d; }
};

/// A rigid pose: world = R·local + t.
struct Pose {
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    Vec3 t = Vec3::Zero();
    Vec3 apply(const Vec3& p) const { return R * p + t; }
    Vec3 rotate(const Vec3& v) const { return R * v; }
    /// Roll, pitch, yaw in degrees (applied as Rz(yaw)·Ry(pitch)·Rx(roll)), position in metres.
    static Pose fromRpyDeg(const Vec3& position_m, const Vec3& rpy_deg);
};

/// Axis-aligned box in world coordinates.
struct Aabb {
    Vec3 lo = Vec3::Constant(kInf);
    Vec3 hi = Vec3::Constant(-kInf);
    bool empty() const { return (lo.array() > hi.array()).any(); }
    void extend(const Vec3& p)
    {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    /// Clips [t0, t1] to the slab intersection; false when the ray misses.
    bool clip(const Ray& r, double& t0, double& t1) const;
    /// The same with the ray's inverse direction given (1/d on each axis whose d is not 0): one
    /// ray against many boxes divides once.
    bool clip(const Ray& r, const Vec3& inv_d, double& t0, double& t1) const;
    /// The inverse direction clip() takes: 1/d, 0 on an axis without motion.
    static Vec3 inverseDirection(const Ray& r);
};

}  // namespace smokescan
