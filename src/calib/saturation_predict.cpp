#include "smokescan/calib/saturation_predict.hpp"

#include <algorithm>
#include <cmath>

#include "smokescan/core/error.hpp"
#include "smokescan/core/overloaded.hpp"
#include "smokescan/core/random.hpp"

namespace smokescan {
namespace {

Vec3 centreOf(const Surface& s)
{
    return std::visit(Overloaded{
                          [&](const QuadShape& q) -> Vec3 { return q.corner_m + 0.5 * (q.edge_u_m + q.edge_v_m); },
                          [&](const CylinderShape& c) -> Vec3 { return s.pose.t + Vec3(0, 0, 0.5 * c.height_m); },
                          [&](const BoxShape&) -> Vec3 { return s.pose.t; },  // centred on its pose
                          [&](const MeshShape&) -> Vec3 { return s.pose.t; },  // the mesh's origin
                      },
                      s.shape);
}

}  // namespace

SaturationPredictor::SaturationPredictor(const Scene& scene, const SurfaceSet& surfaces, const SaturationCurve& curve,
                                         const std::string& camera, const std::string& target_prefix)
    : curve_(curve)
{
    const Camera* cam = scene.findCamera(camera);
    if (!cam)
        throw Error(scene.source, camera.empty() ? "the scene has no camera" : "no camera named '" + camera + "'");
    Vec3 centre = Vec3::Zero();
    int n = 0;
    for (const auto& s : scene.surfaces)
        if (s.name.rfind(target_prefix, 0) == 0) {
            centre += centreOf(s);
            ++n;
        }
    if (n == 0) throw Error(scene.source, "has no target surfaces named '" + target_prefix + "*'");
    centre /= n;
    const Vec3 d = centre - cam->pose.t;
    ray_ = Ray{cam->pose.t, d.normalized()};
    const SurfaceHit h = surfaces.closest(ray_, d.norm() * 1.5);
    if (!h.hit || scene.surfaces[size_t(h.surface)].name.rfind(target_prefix, 0) != 0)
        throw Error(scene.source, "the camera's line of sight to the target's centre is blocked");
    path_m_ = h.t_m;
}

double SaturationPredictor::column(const SmokeField& field) const
{
    BeamQuery q;
    q.wavelength_nm = 550;
    const BeamSmoke s = field.trace(ray_, 0.0, path_m_, q);
    return s.column_regional + s.column_local;
}

SaturationSeries simulateSaturation(const SaturationFrameFn& frame, const SaturationSimConfig& cfg)
{
    if (!(cfg.rate_hz > 0) || !std::isfinite(cfg.rate_hz)) throw Error("--saturation-rate", "must be finite and > 0");
    if (!(cfg.sigma >= 0)) throw Error("--saturation-sigma", "must be >= 0");
    if (!(cfg.to_s >= cfg.from_s)) throw Error("--to", "must not precede --from");
    const long long n = (long long)std::floor((cfg.to_s - cfg.from_s) * cfg.rate_hz + 1e-9);
    if (n > 10'000'000) throw Error("--saturation-rate", "more than ten million frames requested");
    SaturationSeries s;
    // Noise for column c of frame k depends on (seed, c, k) only; column 0 is the whole target.
    auto noisy = [&](double S, uint64_t column, long long k) {
        if (cfg.sigma > 0) S += cfg.sigma * KeyedRng(cfg.seed, 0x5A7u + column, uint64_t(k)).normal();
        return std::clamp(S, 0.0, 1.0);
    };
    for (long long k = 0; k <= n; ++k) {
        const double t = cfg.from_s + double(k) / cfg.rate_hz;
        const SaturationFrame f = frame(t, uint64_t(k));
        if (k == 0)
            for (const auto& [name, v] : f.patches) {
                s.patch_names.push_back(name);
                s.patch.emplace_back();
            }
        s.time_s.push_back(t + cfg.clock_offset_s);
        s.saturation.push_back(noisy(f.saturation, 0, k));
        for (size_t p = 0; p < s.patch_names.size(); ++p) {
            const auto it = f.patches.find(s.patch_names[p]);
            if (it == f.patches.end())
                throw Error("saturation",
                            "frame at t = " + std::to_string(t) + " s does not show patch '" + s.patch_names[p] + "'");
            s.patch[p].push_back(noisy(it->second, 1 + p, k));
        }
    }
    return s;
}

SaturationSeries simulateSaturation(const Scene& scene, const SaturationPredictor& predictor,
                                    const SaturationSimConfig& cfg)
{
    return simulateSaturation(
        [&](double t, uint64_t) {
            return SaturationFrame{predictor.saturation(SmokeField::at(scene.volumes, t)), {}};
        },
        cfg);
}

}  // namespace smokescan
