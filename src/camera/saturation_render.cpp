#include "smokescan/camera/saturation_render.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "smokescan/camera/develop.hpp"
#include "smokescan/camera/target_radiance.hpp"
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

/// Mean HSV saturation of the pixels with patch_of == p (p < 0: every target pixel) of a frame,
/// and the standard error that the camera's noise gives it: the spread of the per-pixel
/// difference from the noiseless frame.
std::pair<double, double> patchSaturation(const Image& frame, const Image& noiseless, const std::vector<int>& patch_of,
                                          int p, std::vector<double>* values)
{
    double s = 0, d = 0, d2 = 0;
    long long n = 0;
    for (size_t i = 0; i < patch_of.size(); ++i) {
        if (patch_of[i] < 0 || (p >= 0 && patch_of[i] != p)) continue;
        const float* a = &frame.data[i * 3];
        const float* b = &noiseless.data[i * 3];
        const double sa = hsvSaturation(a[0], a[1], a[2]), diff = sa - hsvSaturation(b[0], b[1], b[2]);
        if (values) values->push_back(sa);
        s += sa;
        d += diff;
        d2 += diff * diff;
        ++n;
    }
    if (n == 0) return {0.0, 0.0};
    const double md = d / n;
    return {s / n, n > 1 ? std::sqrt(std::max(0.0, (d2 - d * md) / (n - 1)) / n) : 0.0};
}

}  // namespace

TargetSaturation measureConvergedSaturation(const Scene& scene, const SurfaceSet& surfaces, const RenderConfig& rc,
                                            const std::string& target_prefix, const TargetRadianceConfig& fcfg,
                                            Image* display, Image* ids)
{
    const TargetPatches target = targetPatches(scene, target_prefix);
    const Camera* cam = scene.findCamera(rc.camera);
    if (!cam) throw Error(scene.source, "no camera named '" + rc.camera + "'");
    const CameraSensor& sensor = cam->sensor;
    const TargetRadiance f = measureTargetRadiance(scene, surfaces, rc, target, sensor, fcfg);
    CameraSensor clean = sensor;
    clean.noise = false;
    clean.bits = 0;
    const Image frame = develop(f.radiance, sensor, f.exposure, rc.seed),
                noiseless = develop(f.radiance, clean, f.exposure, 0);
    TargetSaturation out;
    out.exposure = f.exposure;
    out.spp = f.spp;
    out.rel_error = f.rel_error;
    out.lack_of_fit = f.lack_of_fit;
    // Each batch's field through the same camera noise: their spread is the field's share of the error.
    std::vector<Image> batch_frames;
    for (const Image& b : f.batches) batch_frames.push_back(develop(b, sensor, f.exposure, rc.seed));
    auto floorOf = [&](int p) {  // the noise floor at the mean exposed level of the pixels
        double sum = 0;
        long long n = 0;
        for (size_t i = 0; i < f.patch_of_pixel.size(); ++i)
            if (f.patch_of_pixel[i] >= 0 && (p < 0 || f.patch_of_pixel[i] == p)) {
                sum += f.radiance.data[i * 3] + f.radiance.data[i * 3 + 1] + f.radiance.data[i * 3 + 2];
                n += 3;
            }
        return n > 0 ? greyNoiseSaturation(sensor, f.exposure * sum / double(n)) : 0.0;
    };
    out.floor = floorOf(-1);
    auto measure = [&](int p, SaturationStats& st, double& se) {
        std::vector<double> v;
        const auto [mean, se_camera] = patchSaturation(frame, noiseless, f.patch_of_pixel, p, &v);
        double s = 0, s2 = 0;
        for (const Image& bf : batch_frames) {
            const double m = patchSaturation(bf, noiseless, f.patch_of_pixel, p, nullptr).first;
            s += m;
            s2 += m * m;
        }
        const double B = double(batch_frames.size()), mb = s / B;
        const double se_field = B > 1 ? std::sqrt(std::max(0.0, (s2 - s * mb) / (B - 1)) / B) : 0.0;
        st = saturationStats(std::move(v));
        st.mean = mean;
        se = std::hypot(se_camera, se_field);
    };
    measure(-1, out.all, out.se);
    for (size_t p = 0; p < target.names.size(); ++p) {
        SaturationStats st;
        double se = 0;
        measure(int(p), st, se);
        if (st.pixels == 0) continue;
        out.patches[target.names[p]] = st;
        out.patch_se[target.names[p]] = se;
        out.patch_floor[target.names[p]] = floorOf(int(p));
        std::array<double, 3> col{{0, 0, 0}};
        for (size_t i = 0; i < f.patch_of_pixel.size(); ++i)
            if (f.patch_of_pixel[i] == int(p))
                for (int c = 0; c < 3; ++c) col[size_t(c)] += f.radiance.data[i * 3 + size_t(c)] / double(st.pixels);
        out.patch_colour[target.names[p]] = col;
        std::vector<double> lum;
        for (size_t i = 0; i < f.patch_of_pixel.size(); ++i)
            if (f.patch_of_pixel[i] == int(p))
                lum.push_back(0.2126 * f.radiance.data[i * 3] + 0.7152 * f.radiance.data[i * 3 + 1] +
                              0.0722 * f.radiance.data[i * 3 + 2]);
        std::sort(lum.begin(), lum.end());
        const double mean_lum = std::accumulate(lum.begin(), lum.end(), 0.0) / double(lum.size());
        std::vector<double>& classes = out.patch_brightness[target.names[p]];
        const size_t K = std::min<size_t>(8, lum.size());
        for (size_t k = 0; k < K && mean_lum > 0; ++k) {
            const size_t a = k * lum.size() / K, b = (k + 1) * lum.size() / K;
            classes.push_back(std::accumulate(lum.begin() + long(a), lum.begin() + long(b), 0.0) / double(b - a) /
                              mean_lum);
        }
        out.patch_share[target.names[p]] = double(st.pixels) / double(std::max(1LL, out.all.pixels));
    }
    if (display) *display = frame;
    if (ids) *ids = f.ids;
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
    if (cfg.field.batch_spp < 1) throw Error("--saturation-spp", "must be >= 1");
    if (cfg.width <= 0 || cfg.height <= 0) throw Error("--saturation-width", "frame size must be > 0");
    // A 1-spp frame now, so that a camera that misses the target fails before any scan is made.
    measureTargetSaturation(scene, surfaces, renderConfigOf(cfg, t_check_s, cfg.seed, 1), cfg.target_prefix);
}

TargetSaturation SaturationRenderer::measure(double time_s, uint64_t frame, Image* display, Image* ids) const
{
    return measureConvergedSaturation(scene_, surfaces_, renderConfigOf(cfg_, time_s, cfg_.seed + frame, 1),
                                      cfg_.target_prefix, cfg_.field, display, ids);
}

const std::string& SaturationRenderer::cameraName() const
{
    const Camera* cam = scene_.findCamera(cfg_.camera);
    if (!cam) throw Error(scene_.source, "no camera named '" + cfg_.camera + "'");
    return cam->name;
}

}  // namespace smokescan
