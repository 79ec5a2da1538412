#include "smokescan/omni/omni_compare.hpp"

#include <cmath>

namespace smokescan {

std::vector<double> laserPerScanline(const OmniFrame& f)
{
    const size_t n = f.omni.range_m.size();
    if (n == 0) return {};
    // The laser's points seen from the camera's axis: the nearest point in bearing per scanline.
    std::vector<double> laser(n, NAN), gap(n, INFINITY);
    const double step = 2 * M_PI / double(n);
    for (size_t i = 0; i < f.laser_range_m.size(); ++i) {
        const double r = f.laser_range_m[i];
        if (!std::isfinite(r)) continue;
        const double a = f.laser_angle_rad[i];
        const Vec3 p = scanPlanePoint(f.laser_pose, a, r);
        const Vec3 q = f.camera_pose.R.transpose() * (p - f.camera_pose.t);
        const double bearing = std::atan2(q.y(), q.x()), d = std::hypot(q.x(), q.y());
        double u = bearing / step;
        if (u < 0) u += double(n);
        const size_t k = size_t(std::llround(u)) % n;
        const double g = std::abs(std::remainder(bearing - f.omni.angle_rad[k], 2 * M_PI));
        if (g < gap[k]) {
            gap[k] = g;
            laser[k] = d;
        }
    }
    return laser;
}

void OmniComparison::add(const OmniFrame& f)
{
    const size_t n = f.omni.range_m.size();
    if (n == 0) return;
    const std::vector<double> laser = laserPerScanline(f);
    for (size_t k = 0; k < n; ++k) {
        if (f.omni.status[k] != OmniRangeStatus::Hit || !std::isfinite(laser[k])) continue;
        const double diff = laser[k] - f.omni.range_m[k];
        if (std::abs(diff) > outlier_m) {
            ++outliers;
            continue;
        }
        ++pairs;
        sum_abs_m += std::abs(diff);
        sum_signed_m += diff;
        sum_pct += 100 * std::abs(diff) / laser[k];
        differences_m.push_back(diff);
    }
}

}  // namespace smokescan
