// Renderer throughput, in one run:
//  1. bocas at 640×480 in smoke: samples/s and seconds per frame; the standard error of the
//     target's mean HSV saturation over independent frames (target: < 0.005 within 10 s).
//  2. the teapot cloud with absorption only, smokescan beside OpenVDB's vdb_render at the same
//     resolution and view: both times, and the mean transmittance difference of each to the exact
//     per-pixel transmittance (smokescan's optical-depth walk along each pixel's centre ray).
#include <unistd.h>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "scene_text.hpp"
#include "smokescan/camera/saturation.hpp"
#include "smokescan/render/renderer.hpp"
#include "smokescan/scene/scene_io.hpp"

using namespace smokescan;
namespace fs = std::filesystem;

namespace {

double seconds(std::chrono::steady_clock::time_point t0)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void bocas(double time_s, int spp, int frames)
{
    const Scene scene = loadScene("bocas");
    const SurfaceSet set(scene);
    std::vector<int> target_ids;
    for (size_t i = 0; i < scene.surfaces.size(); ++i)
        if (scene.surfaces[i].name.rfind("target_", 0) == 0) target_ids.push_back(int(i));
    std::vector<double> means;
    double secs = 0;
    long long samples = 0;
    for (int f = 0; f < frames; ++f) {
        RenderConfig cfg;
        cfg.time_s = time_s;
        cfg.spp = spp;
        cfg.seed = uint64_t(100 + f);
        cfg.progress = false;
        const RenderResult r = render(scene, set, cfg);
        secs += r.seconds;
        samples += r.samples;
        const Image disp = toDisplay(r.radiance, 0.0);
        const auto st = maskedSaturation(disp, [&](int x, int y) {
            const int id = int(r.ids.at(x, y, 0));
            return std::find(target_ids.begin(), target_ids.end(), id) != target_ids.end();
        });
        means.push_back(st.mean);
        std::printf("  frame %d: %.2f s, target saturation mean %.4f over %lld px\n", f, r.seconds, st.mean, st.pixels);
    }
    double m = 0, v = 0;
    for (double x : means) m += x;
    m /= means.size();
    for (double x : means) v += (x - m) * (x - m);
    const double se_frame = std::sqrt(v / (means.size() - 1));  // spread of one frame's mean
    std::printf(
        "bocas 640x480, t = %.0f s, %d spp: %.2f s/frame, %.3f M samples/s, target saturation %.4f, "
        "standard error of one frame's mean %.5f (from %d frames)\n",
        time_s, spp, secs / frames, samples / secs / 1e6, m, se_frame, frames);
}

void teapot()
{
    // A third-party file (no licence to ship it): found through SMOKESCAN_EXTERNAL_VDB, else skipped.
    const char* dir = std::getenv("SMOKESCAN_EXTERNAL_VDB");
    const std::string vdb = dir && *dir ? std::string(dir) + "/teapot_cloud.vdb" : "";
    if (vdb.empty() || !std::filesystem::is_regular_file(vdb)) {
        std::printf("teapot cloud: skipped (set SMOKESCAN_EXTERNAL_VDB to the folder holding teapot_cloud.vdb)\n");
        return;
    }
    const int W = 320, H = 240;
    const double density_scale = 0.02, sigma = 100.0;  // σ_a = 100 · 0.02 · stored value [1/m]
    const std::string toml = smokescan::test::SceneText()
                                 .ambient(1.0)
                                 .camera({0, -4, 0}, {0, 0, 0}, W, H, 40)
                                 .vdbSmoke(vdb, density_scale, "{ sigma_t_550 = 100.0, angstrom = 0.0, albedo = 0.0 }");
    const Scene scene = parseScene(toml, "teapot-bench", "");
    const SurfaceSet set(scene);
    RenderConfig cfg;
    cfg.spp = 16;
    cfg.progress = false;
    const RenderResult ours = render(scene, set, cfg);  // radiance = transmittance to the sky

    // Exact per-pixel transmittance of the centre rays.
    const auto& grid = *std::get<std::shared_ptr<const DensityGrid>>(scene.volumes[0].source);
    const auto cam = makeCamera(scene.cameras[0]);
    std::vector<double> exact(size_t(W) * H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            Ray r;
            cam->generateRay(x + 0.5, y + 0.5, r);
            exact[size_t(y) * W + x] = std::exp(-sigma * grid.integrate(r, 0, 100));
        }

    double d_ours = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) d_ours += std::abs(ours.radiance.at(x, y, 1) - exact[size_t(y) * W + x]);
    const double n = double(W) * H;
    std::printf("teapot cloud %dx%d, absorption only: smokescan %.2f s (16 spp), mean |T − T_exact| %.4f\n", W, H,
                ours.seconds, d_ours / n);

    // vdb_render: absorption only, same view; alpha is opacity, so T = 1 − alpha. Once with its
    // defaults (which drop densities below a cutoff of 0.005), once with the cutoff off.
    for (const char* extra : {"", " -cutoff 0"}) {
        const fs::path out =
            fs::temp_directory_path() / ("smokescan_vdb_render_" + std::to_string(::getpid()) + ".exr");
        char cmd[1024];
        std::snprintf(cmd, sizeof cmd,
                      "vdb_render %s %s -res %dx%d -fov 40 -translate 0,-4,0 -lookat 0,0,0 -up 0,0,1 -absorb %g,%g,%g "
                      "-scatter 0,0,0%s >/dev/null 2>&1",
                      vdb.c_str(), out.string().c_str(), W, H, sigma * density_scale, sigma * density_scale,
                      sigma * density_scale, extra);
        const auto t0 = std::chrono::steady_clock::now();
        const int rc = std::system(cmd);
        const double vdb_secs = seconds(t0);
        if (rc != 0 || !fs::exists(out)) {
            std::printf("  vdb_render%s: unavailable or failed\n", extra);
            continue;
        }
        const Image v = readImage(out.string());
        fs::remove(out);
        if (v.width != W || v.height != H || v.channels < 4) continue;
        double d_vdb = 0, d_both = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const double tv = 1.0 - v.at(x, y, 3);
                d_vdb += std::abs(tv - exact[size_t(y) * W + x]);
                d_both += std::abs(tv - ours.radiance.at(x, y, 1));
            }
        std::printf("  vdb_render%s: %.2f s, mean |T − T_exact| %.4f, mean |T_smokescan − T_vdb_render| %.4f\n",
                    *extra ? extra : " (defaults)", vdb_secs, d_vdb / n, d_both / n);
    }
}

}  // namespace

int main(int argc, char** argv)
{
    const int spp = argc > 1 ? std::atoi(argv[1]) : 2;
    const int frames = argc > 2 ? std::atoi(argv[2]) : 4;
    std::printf("threads: all cores\n");
    bocas(100.0, spp, frames);
    teapot();
}
