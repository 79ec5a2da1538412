#include "smokescan/calib/saturation_predict.hpp"

#include <algorithm>
#include <cmath>

#include "smokescan/core/error.hpp"
#include "smokescan/core/overloaded.hpp"
#include "smokescan/core/random.hpp"
#include "smokescan/render/camera.hpp"

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
    // A target made of patches side by side (BOCAS's strips): the line of sight to their centroid,
    // which lies on one of them. Targets apart (the centroid between them, on none): the line to
    // the centre of each patch the camera sees, nothing else first on it.
    std::vector<size_t> patches;
    Vec3 centroid = Vec3::Zero();
    for (size_t i = 0; i < scene.surfaces.size(); ++i)
        if (scene.surfaces[i].name.rfind(target_prefix, 0) == 0) {
            patches.push_back(i);
            centroid += centreOf(scene.surfaces[i]);
        }
    if (patches.empty()) throw Error(scene.source, "has no target surfaces named '" + target_prefix + "*'");
    centroid /= double(patches.size());
    auto seen = [&](const Vec3& at, bool any_patch, size_t patch) {
        const Vec3 d = at - cam->pose.t;
        const Ray ray{cam->pose.t, d.normalized()};
        if (!inView(*cam, ray.d)) return false;  // outside its image
        const SurfaceHit h = surfaces.closest(ray, d.norm() * 1.5);
        // On the target: the first surface on the line is a patch (this one, for a patch's own
        // line; a box's or cylinder's centre lies inside it, so the hit comes before the centre).
        const bool on = h.hit &&
            (any_patch ? std::find(patches.begin(), patches.end(), size_t(h.surface)) != patches.end()
                       : size_t(h.surface) == patch);
        if (on) sights_.push_back({ray, h.t_m});
        return on;
    };
    if (!seen(centroid, true, 0))
        for (size_t i : patches) seen(centreOf(scene.surfaces[i]), false, i);
    if (sights_.empty())
        throw Error(scene.source,
                    "the camera sees the centre of none of the target's patches ('" + target_prefix +
                        "*'): each lies outside its image or another surface hides it");
}

double SaturationPredictor::Sight::column(const SmokeField& field) const
{
    BeamQuery q;
    q.wavelength_nm = 550;
    const BeamSmoke b = field.trace(ray, 0.0, path_m, q);
    return b.column_regional + b.column_local;
}

double SaturationPredictor::column(const SmokeField& field) const
{
    double sum = 0;
    for (const Sight& s : sights_) sum += s.column(field);
    return sum / double(sights_.size());
}

double SaturationPredictor::density(const SmokeField& field) const
{
    double sum = 0;
    for (const Sight& s : sights_) sum += s.column(field) / s.path_m;
    return sum / double(sights_.size());
}

double SaturationPredictor::path_m() const
{
    double sum = 0;
    for (const Sight& s : sights_) sum += s.path_m;
    return sum / double(sights_.size());
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
