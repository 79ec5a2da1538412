#include "smokescan/calib/saturation_render.hpp"

#include <algorithm>
#include <vector>

#include "smokescan/core/error.hpp"
#include "smokescan/render/renderer.hpp"

namespace smokescan {

TargetSaturation measureTargetSaturation(const Scene& scene, const SurfaceSet& surfaces, const RenderConfig& rc,
                                         const std::string& target_prefix, Image* display, Image* ids)
{
    // Surface index → patch number (−1: not the target).
    std::vector<int> patch_of(scene.surfaces.size(), -1);
    std::vector<std::string> names;
    for (size_t i = 0; i < scene.surfaces.size(); ++i) {
        const std::string& n = scene.surfaces[i].name;
        if (n.rfind(target_prefix, 0) != 0) continue;
        const std::string p = n.substr(target_prefix.size());
        const auto it = std::find(names.begin(), names.end(), p);
        patch_of[i] = int(it - names.begin());
        if (it == names.end()) names.push_back(p);
    }
    if (names.empty()) throw Error(scene.source, "no target surfaces (names starting with '" + target_prefix + "')");
    const RenderResult r = render(scene, surfaces, rc);
    TargetSaturation out;
    const Image disp = toDisplay(r.radiance, 0.0, &out.exposure);
    auto patchAt = [&](int x, int y) {
        const int id = int(r.ids.at(x, y, 0));
        return id >= 0 && size_t(id) < patch_of.size() ? patch_of[size_t(id)] : -1;
    };
    out.all = maskedSaturation(disp, [&](int x, int y) { return patchAt(x, y) >= 0; });
    if (out.all.pixels == 0) throw Error(scene.source, "the camera does not see the target '" + target_prefix + "*'");
    for (size_t p = 0; p < names.size(); ++p) {
        const auto s = maskedSaturation(disp, [&](int x, int y) { return patchAt(x, y) == int(p); });
        if (s.pixels > 0) out.patches[names[p]] = s;
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

SaturationRenderer::SaturationRenderer(const Scene& scene, const SurfaceSet& surfaces, const SaturationRenderConfig& cfg,
                                       double t_check_s)
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
