// `smokescan render`: camera frames of a scene through its smoke.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "commands.hpp"
#include "smokescan/bag/scan_bag.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/io/run_files.hpp"
#include "smokescan/omni/birdseye.hpp"
#include "smokescan/pipeline/render_run.hpp"
#include "smokescan/render/omni_camera.hpp"
#include "smokescan/render/renderer.hpp"
#include "smokescan/scene/scene_io.hpp"

namespace smokescan::cli {
namespace {

struct RenderArgs {
    std::string scene = "bocas", out, exr, ids, exposure = "auto", birdseye, bag;
    BirdseyeConfig bird;
    RenderConfig cfg;
    double from = NAN, to = NAN, every = 0;
    int width = -1, height = -1;  // -1: the camera's
    double floor_z = 0;
};

/// Fails before any work when an output cannot be written: wrong extension.
void checkFormat(const std::string& path, bool float_only)
{
    if (path.empty()) return;
    if (!isImageExtension(path)) throw Error(path, "unknown image format (exr, png, jpg, tif)");
    if (float_only && std::filesystem::path(path).extension() != ".exr")
        throw Error(path, "must be an .exr (it holds linear floats)");
}

std::string expand(const std::string& pattern, int index, double t)
{
    std::string s = pattern;
    char buf[32];
    std::snprintf(buf, sizeof buf, "%04d", index);
    for (size_t p; (p = s.find("{i}")) != std::string::npos;) s.replace(p, 3, buf);
    std::snprintf(buf, sizeof buf, "%07.2f", t);
    for (size_t p; (p = s.find("{t}")) != std::string::npos;) s.replace(p, 3, buf);
    return s;
}

int runRender(const RenderArgs& a)
{
    double exposure = 0;
    if (a.exposure != "auto") {
        char* end = nullptr;
        exposure = std::strtod(a.exposure.c_str(), &end);
        if (end == a.exposure.c_str() || *end || !(exposure > 0 && exposure <= 1e6))
            throw Error("--exposure", "must be 'auto' or a number in (0, 1e6], got '" + a.exposure + "'");
    }
    std::vector<double> times = {a.cfg.time_s};
    const bool series = a.every > 0;
    if (series) {
        if (std::isnan(a.from) || std::isnan(a.to) || a.to < a.from) throw Error("--every", "needs --from <= --to");
        if ((a.to - a.from) / a.every + 1 > double(limits::kFrames))
            throw Error("--every",
                        "would render " + limits::count(std::floor((a.to - a.from) / a.every) + 1) +
                            " frames (at most " + std::to_string(limits::kFrames) + ")");
        times.clear();
        // Each named output holds one frame: its name must change with the frame.
        for (int k = 0; a.from + k * a.every <= a.to + 1e-9; ++k) times.push_back(a.from + k * a.every);
        for (const std::string* p : {&a.out, &a.exr, &a.ids, &a.birdseye})
            if (!p->empty() && p->find("{i}") == std::string::npos && p->find("{t}") == std::string::npos)
                throw Error(*p, "a time series needs {i} (frame index) or {t} (time) in each output name");
    }
    if (!series && (!std::isnan(a.from) || !std::isnan(a.to)))
        throw Error(std::isnan(a.from) ? "--to" : "--from", "makes a time series with --every (and --from, --to)");
    if (a.out.empty() && a.bag.empty()) throw Error("--out", "give where the frames go: --out FILE, --bag DIR or both");
    // A ROS stamp counts from 0 s, below 2^31 s: checked before any frame is rendered.
    if (!a.bag.empty() && (times.front() < 0 || times.back() >= 2147483648.0))
        throw Error(series ? "--from" : "--time", "a bag's stamps lie in [0, 2^31) s");
    checkFormat(a.out, false);
    checkFormat(a.exr, true);
    checkFormat(a.ids, true);
    checkFormat(a.birdseye, false);
    const Scene scene = loadScene(a.scene);
    RunFiles files;
    recordSceneInputs(files, a.scene, scene);
    for (size_t k = 0; k < times.size(); ++k) {
        if (!a.out.empty()) files.output(expand(a.out, int(k), times[k]), "--out");
        files.output(expand(a.exr, int(k), times[k]), "--exr");
        files.output(expand(a.ids, int(k), times[k]), "--ids");
        files.output(expand(a.birdseye, int(k), times[k]), "--birdseye");
    }
    files.outputFolder(a.bag, "--bag");
    const SurfaceSet surfaces(scene);
    const Camera* scene_cam = scene.findCamera(a.cfg.camera);
    if (!a.birdseye.empty() && scene_cam && scene_cam->kind != CameraKind::Omni)
        throw Error("--birdseye", "needs an omni camera (camera '" + scene_cam->name + "' is a pinhole)");
    std::unique_ptr<ScanBag> bag;
    if (!a.bag.empty()) bag = std::make_unique<ScanBag>(a.bag, scene);
    for (size_t k = 0; k < times.size(); ++k) {
        RenderRunConfig rc;
        rc.render = a.cfg;
        rc.render.time_s = times[k];
        rc.render.width = std::max(0, a.width);
        rc.render.height = std::max(0, a.height);
        rc.exposure = exposure;
        const RenderedFrame f = renderFrame(scene, surfaces, rc);
        const RenderResult& r = f.result;
        const Image& frame = f.display;
        const Camera& c = f.camera;
        const std::string out = a.out.empty() ? a.bag : expand(a.out, int(k), times[k]);
        if (!a.out.empty()) writeImage(files.stage(out), frame);
        if (bag) bag->addImage(frame, times[k], times[k], *scene_cam);  // render found the camera
        if (!a.exr.empty()) writeImage(files.stage(expand(a.exr, int(k), times[k])), r.radiance);
        if (!a.ids.empty()) writeImage(files.stage(expand(a.ids, int(k), times[k])), r.ids);
        if (!a.birdseye.empty()) {
            BirdseyeConfig bc = a.bird;
            bc.height_m = c.pose.t.z() - a.floor_z;
            if (!(bc.height_m > 0)) throw Error("--floor-z", "the camera is not above the floor");
            const auto omni = makeCamera(c);  // an omni camera (checked above)
            writeImage(files.stage(expand(a.birdseye, int(k), times[k])),
                       birdseye(frame, dynamic_cast<const OmniCamera&>(*omni), bc));
        }
        say("t = %.2f s: %s (%dx%d, %d spp, %.2f s, %.2f M samples/s, exposure %.4g)\n", times[k],
            printable(out).c_str(), r.radiance.width, r.radiance.height, rc.render.spp, r.seconds,
            r.samples / r.seconds / 1e6, f.exposure);
    }
    if (bag) bag->finish();
    files.commit([&] {
        if (bag) bag->commit();
    });
    return 0;
}

}  // namespace

void addRender(CLI::App& app, Runner& run)
{
    auto a = std::make_shared<RenderArgs>();
    auto* c = app.add_subcommand("render", "Render camera frames through the smoke (volumetric path tracing)");
    c->add_option("scene", a->scene, "Built-in scene name or scene file (.toml)")->capture_default_str();
    c->add_option("--time", a->cfg.time_s, "Scene time [s]")->capture_default_str()->check(finite());
    c->add_option("--spp", a->cfg.spp, "Samples per pixel")->capture_default_str()->check(intRange(1, limits::kSpp));
    c->add_option("--out", a->out, "8-bit sRGB frame (.png, .jpg, .tif); {i}/{t} in a time series");
    c->add_option("--bag", a->bag,
                  "Also (or instead) write the frames as a ROS 2 bag: a new folder, /camera/image (docs/bags.md)")
        ->check(nonEmpty());
    c->add_option("--exr", a->exr, "Also write linear radiance (.exr)");
    c->add_option("--ids", a->ids, "Also write object id, material id and depth AOVs (.exr)");
    c->add_option("--camera", a->cfg.camera, "Scene camera name (default: the first)");
    c->add_option("--width", a->width, "Override the camera's width [px]")->check(intRange(1, limits::kFrameSide));
    c->add_option("--height", a->height, "Override the camera's height [px]")->check(intRange(1, limits::kFrameSide));
    c->add_option("--seed", a->cfg.seed, "Random seed")->transform(seedRule())->capture_default_str();
    c->add_option("--max-depth", a->cfg.max_depth, "Scattering/bounce events per path")
        ->capture_default_str()
        ->check(intRange(0, limits::kPathDepth));
    c->add_option("--exposure", a->exposure, "'auto' (average metering to 18 % grey) or a radiance scale")
        ->capture_default_str();
    c->add_option("--birdseye", a->birdseye, "Also write the floor seen from above (omni cameras; PNG)");
    c->add_option("--birdseye-size", a->bird.size_px, "Side of --birdseye [px]")
        ->capture_default_str()
        ->check(intRange(1, limits::kFrameSide));
    c->add_option("--birdseye-scale", a->bird.metres_per_px, "Floor metres per --birdseye pixel")
        ->capture_default_str()
        ->check(positive());
    c->add_option("--floor-z", a->floor_z, "Floor height for --birdseye [m]")->capture_default_str()->check(finite());
    c->add_option("--from", a->from, "Time series: first time [s]")->check(finite());
    c->add_option("--to", a->to, "Time series: last time [s]")->check(finite());
    c->add_option("--every", a->every, "Time series: interval [s]")->check(positive());
    c->callback([a, &run] { run = [a] { return runRender(*a); }; });
}

}  // namespace smokescan::cli
