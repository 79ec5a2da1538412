#include "smokescan/omni/scanline_truth.hpp"

#include <algorithm>
#include <cmath>

#include "smokescan/core/error.hpp"
#include "smokescan/media/smoke.hpp"
#include "smokescan/scene/surfaces.hpp"

namespace smokescan {

ScanlineTruth scanlineTruth(const SurfaceSet& surfaces, const SmokeField& smoke, const Pose& camera_pose,
                            double height_m, const std::vector<double>& azimuth_rad, double max_range_m,
                            const ScanlineTruthConfig& cfg)
{
    const auto positive = [](double v) { return v > 0 && std::isfinite(v); };
    if (!positive(height_m)) throw Error("height_m", "must be positive and finite");
    if (!positive(max_range_m)) throw Error("max_range_m", "must be positive and finite");
    if (!positive(cfg.probe_step_m)) throw Error("probe_step_m", "must be positive and finite");
    if (!positive(cfg.reach_m)) throw Error("reach_m", "must be positive and finite");
    if (height_m / cfg.probe_step_m > 1e5) throw Error("probe_step_m", "gives over 100000 probes per scanline");
    const Vec3 eye = camera_pose.t;
    const double floor_z = eye.z() - height_m;
    ScanlineTruth out;
    out.range_m.reserve(azimuth_rad.size());
    out.column.reserve(azimuth_rad.size());
    for (double a : azimuth_rad) {
        Vec3 dir = camera_pose.rotate(Vec3(std::cos(a), std::sin(a), 0));
        dir.z() = 0;
        if (!(dir.norm() > 1e-9)) throw Error("camera_pose", "the omni camera must look straight down");
        dir.normalize();
        double nearest = kInf;
        int surface = -1;
        for (double z = floor_z + cfg.probe_step_m; z < eye.z(); z += cfg.probe_step_m) {
            const SurfaceHit h = surfaces.closest(Ray{Vec3(eye.x(), eye.y(), z), dir}, std::min(nearest, cfg.reach_m));
            if (h.hit && h.t_m < nearest) {
                nearest = h.t_m;
                surface = h.surface;
            }
        }
        out.range_m.push_back(nearest);
        out.surface.push_back(surface);
        // The line of sight to the floor at the obstacle's foot.
        const Vec3 foot = Vec3(eye.x(), eye.y(), floor_z) + std::min(nearest, max_range_m) * dir;
        const Vec3 sight = foot - eye;
        const double len = sight.norm();
        out.sight.push_back(Ray{eye, sight / len});
        out.sight_m.push_back(len);
        const BeamSmoke b = smoke.trace(out.sight.back(), 0, len, BeamQuery{});
        out.column.push_back(b.column_regional + b.column_local);
    }
    return out;
}

}  // namespace smokescan
