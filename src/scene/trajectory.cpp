#include "smokescan/scene/trajectory.hpp"

#include <algorithm>
#include <cmath>

namespace smokescan {
namespace {

/// Index k of the segment [k, k+1] holding t (clamped), and the fraction along it.
std::pair<size_t, double> locate(const std::vector<Keyframe>& kf, double t)
{
    if (kf.size() < 2 || t <= kf.front().time_s) return {0, 0.0};
    if (t >= kf.back().time_s) return {kf.size() - 2, 1.0};
    const auto it = std::upper_bound(kf.begin(), kf.end(), t, [](double v, const Keyframe& k) { return v < k.time_s; });
    const size_t k = size_t(it - kf.begin()) - 1;
    return {k, (t - kf[k].time_s) / (kf[k + 1].time_s - kf[k].time_s)};
}

}  // namespace

Pose Robot::at(double t_s) const
{
    if (keyframes.empty()) return Pose{};
    if (keyframes.size() == 1) return Pose::fromRpyDeg(keyframes[0].position, Vec3(0, 0, keyframes[0].yaw_deg));
    const auto [k, f] = locate(keyframes, t_s);
    const Keyframe &a = keyframes[k], &b = keyframes[k + 1];
    const double dyaw = std::remainder(b.yaw_deg - a.yaw_deg, 360.0);
    return Pose::fromRpyDeg(a.position + f * (b.position - a.position), Vec3(0, 0, a.yaw_deg + f * dyaw));
}

double Robot::distanceAt(double t_s) const
{
    if (keyframes.size() < 2) return 0;
    const auto [k, f] = locate(keyframes, t_s);
    double d = 0;
    for (size_t i = 0; i < k; ++i) d += (keyframes[i + 1].position - keyframes[i].position).norm();
    return d + f * (keyframes[k + 1].position - keyframes[k].position).norm();
}

}  // namespace smokescan
