#include "smokescan/camera/saturation_render.hpp"

#include <algorithm>
#include <vector>

#include "smokescan/core/error.hpp"
#include "smokescan/render/renderer.hpp"

namespace smokescan {

TargetPatches targetPatches(const Scene& scene, const std::string& prefix)
{
    TargetPatches t;
    t.patch_of.assign(scene.surfaces.size(), -1);
    for (size_t i = 0; i < scene.surfaces.size(); ++i) {
        const std::string& n = scene.surfaces[i].name;
        if (n.rfind(prefix, 0) != 0) continue;
        const std::string p = n.substr(prefix.size());
        const auto it = std::find(t.names.begin(), t.names.end(), p);
        t.patch_of[i] = int(it - t.names.begin());
        if (it == t.names.end()) t.names.push_back(p);
    }
    if (t.names.empty()) throw Error(scene.source, "has no target surfaces named '" + prefix + "*'");
    return t;
}

TargetSaturation measureTargetSaturation(const Scene& scene, const SurfaceSet& surfaces, const RenderConfig& rc,
                                         const std::string& target_prefix, Image* display, Image* ids)
{
    const TargetPatches target = targetPatches(scene, target_prefix);
    const RenderResult r = render(scene, surfaces, rc);
    TargetSaturation out;
    const Image disp = toDisplay(r.radiance, 0.0, &out.exposure);
    auto patchAt = [&](int x, int y) { return target.of(int(r.ids.at(x, y, 0))); };
    out.all = maskedSaturation(disp, [&](int x, int y) { return patchAt(x, y) >= 0; });
    if (out.all.pixels == 0) throw Error(scene.source, "the camera does not see the target '" + target_prefix + "*'");
    for (size_t p = 0; p < target.names.size(); ++p) {
        const auto s = maskedSaturation(disp, [&](int x, int y) { return patchAt(x, y) == int(p); });
        if (s.pixels > 0) out.patches[target.names[p]] = s;
    }
    if (display) *display = disp;
    if (ids) *ids = r.ids;
    return out;
}

namespace {
RenderConfig renderConfigOf(const SaturationRenderConfig& c, double time_s, uint64_t seed, int spp)
{
    RenderConfig rc;
    rc.time_s = time_s;
    rc.spp = spp;
    rc.width = c.width;
    rc.height = c.height;
    rc.camera = c.camera;
    rc.seed = seed;
    rc.progress = false;
    return rc;
}
}  // namespace

SaturationRenderer::SaturationRenderer(const Scene& scene, const SurfaceSet& surfaces,
                                       const SaturationRenderConfig& cfg, double t_check_s)
    : scene_(scene), surfaces_(surfaces), cfg_(cfg)
{
    if (cfg.spp < 1) throw Error("--saturation-spp", "must be >= 1");
    if (cfg.width <= 0 || cfg.height <= 0) throw Error("--saturation-width", "frame size must be > 0");
    // A 1-spp frame now, so that a camera that misses the target fails before any scan is made.
    measureTargetSaturation(scene, surfaces, renderConfigOf(cfg, t_check_s, cfg.seed, 1), cfg.target_prefix);
}

TargetSaturation SaturationRenderer::measure(double time_s, uint64_t frame, Image* display, Image* ids) const
{
    return measureTargetSaturation(scene_, surfaces_, renderConfigOf(cfg_, time_s, cfg_.seed + frame, cfg_.spp),
                                   cfg_.target_prefix, display, ids);
}

}  // namespace smokescan
