// `smokescan calibrate` (the paper's Fig. 7) and `smokescan saturation` (target saturation of frames).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <regex>
#include <sstream>

#include "commands.hpp"
#include "progress.hpp"
#include "smokescan/calib/calibration.hpp"
#include "smokescan/camera/frame_saturation.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/fit/bag_saturation.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/io/run_files.hpp"
#include "smokescan/io/text_input.hpp"
#include "smokescan/pipeline/calibrate_run.hpp"
#include "smokescan/pipeline/saturation_run.hpp"
#include "smokescan/scene/scene_io.hpp"

namespace smokescan::cli {
namespace {
namespace fs = std::filesystem;

/// χ²/dof, or "n/a" when the fit has no degrees of freedom left.
std::string chi2PerDof(double chi2, int dof) { return dof > 0 ? fmt("%.2f", chi2 / dof) : std::string("n/a"); }

struct CalibArgs {
    std::string scene = "bocas", out, plot, densities;
    CalibrateConfig cfg;
};

int runCalibrate(const CalibArgs& a)
{
    CalibrateConfig cfg = a.cfg;
    if (!a.densities.empty()) cfg.densities = parseNumberList(a.densities, "--densities");
    const Scene scene = loadScene(a.scene);
    RunFiles files;
    recordSceneInputs(files, a.scene, scene);
    files.output(a.out, "--out");
    files.output(a.plot, "--plot");
    if (!a.plot.empty() && !isImageExtension(a.plot)) throw Error(a.plot, "unknown image format (png, exr, jpg, tif)");
    const Progress progress("calibrate", "frames");
    RunControl control;
    control.progress = [&](long long done, long long total) { progress.update(int(done), int(total)); };
    const CalibrationResult r = runCalibration(scene, cfg, control);
    writeCalibrationJson(files.stage(a.out), r, cfg, scene.source);
    if (!a.plot.empty()) writeCalibrationPlot(files.stage(a.plot), r, cfg);
    files.commit();
    const auto& f = r.fit;
    say("fit: S0 = %.4f ± %.4f, a = %.4f ± %.4f, b = %.1f ± %.1f /density; chi2/dof = %s, R² = %.5f%s\n", f.curve.S0,
        f.std_error[0], f.curve.a, f.std_error[1], f.curve.b, f.std_error[2], chi2PerDof(f.chi2, f.dof).c_str(), f.r2,
        f.converged ? "" : " (NOT CONVERGED)");
    say("saturation %.2f at density %.5f ± %.5f; penetration power over %.2f m = %.5f ± %.5f density·m "
        "(paper: 0.0028, 0.007); engine unit factor %.3f\n",
        cfg.threshold_saturation, r.threshold_density, r.threshold_density_se, cfg.path_m, r.penetration_power,
        r.penetration_power_se, r.engine_unit_factor);
    if (r.mix.curve.target.empty() || r.mix.std_error.empty())
        say("colour-mixing curve: not fitted (%s)\n",
            r.mix.message.empty() ? "its covariance is not identified" : r.mix.message.c_str());
    else {
        say("colour-mixing curve%s, all patches, one extinction: b = %.1f ± %.1f /density, scattered light RGB 1 : "
            "%.3f : %.3f; chi2/dof = %s (%d dof); saturation %.2f at density %s\n",
            r.mix.converged ? "" : " (NOT CONVERGED)", r.mix.curve.b, r.mix.std_error[0], r.mix.curve.airlight[1],
            r.mix.curve.airlight[2], chi2PerDof(r.mix.chi2, r.mix.dof).c_str(), r.mix.dof, cfg.threshold_saturation,
            r.mix_threshold_density > 0
                ? (fmt("%.5f", r.mix_threshold_density) + " ± " + fmt("%.5f", r.mix_threshold_density_se)).c_str()
                : "not reached in the sweep");
    }
    if (!r.drift.std_error.empty())
        say("  with a light that drifts from warm to grey%s: chi2/dof = %s (%d dof); saturation %.2f at density %s\n",
            r.drift.converged ? "" : " (NOT CONVERGED)", chi2PerDof(r.drift.chi2, r.drift.dof).c_str(), r.drift.dof,
            cfg.threshold_saturation,
            r.drift_threshold_density > 0
                ? (fmt("%.5f", r.drift_threshold_density) + " ± " + fmt("%.5f", r.drift_threshold_density_se)).c_str()
                : "not reached in the sweep");
    const PatchExtinctions& pe = r.patch_mix;
    for (const auto& [name, f] : pe.fits)
        say("  %s alone, under the joint fit's %s light: b = %.1f ± %.1f, chi2/dof = %s\n", name.c_str(),
            r.patch_mix_light.c_str(), f.curve.b, f.std_error[0], chi2PerDof(f.chi2, f.dof).c_str());
    if (pe.dof > 0)
        say("  the patches' b's about their mean %.1f: chi2 = %.2f (%d dof), p = %.3g: %s\n", pe.b_mean, pe.chi2,
            pe.dof, pe.p_value, pe.p_value < 0.01 ? "NOT one extinction" : "consistent with one extinction");
    if (!r.mixing.empty()) {
        const auto at = [&](double rho) {  // the measured density in smoke nearest rho
            const LightMixing* best = &r.mixing.back();
            for (const auto& q : r.mixing)
                if (q.density > 0 && std::abs(q.density - rho) < std::abs(best->density - rho)) best = &q;
            return *best;
        };
        const LightMixing thin = at(0.0005), dense = at(0.008);
        auto ratio = [](const LightMixing& q) {
            return fmt("%.3f", q.scattered[1] / q.scattered[0]) + " : " + fmt("%.3f", q.scattered[2] / q.scattered[0]);
        };
        say("measured from the patches' colours: b = %.1f ± %.1f /density; scattered light RGB 1 : %s at "
            "density %.4f, 1 : %s at %.4f\n",
            r.mixing_b, r.mixing_b_se, ratio(thin).c_str(), thin.density, ratio(dense).c_str(), dense.density);
    }
    double worst = 0;
    for (double e : r.rel_error) worst = std::max(worst, e);
    if (worst > cfg.field.rel_error)
        say("note: the target radiance reached a relative error of %.3f, not the %.3f asked (--max-batches %d)\n",
            worst, cfg.field.rel_error, cfg.field.max_batches);
    say("wrote %s%s%s (%zu frames, %.1f s)\n", a.out.c_str(), a.plot.empty() ? "" : " and ", a.plot.c_str(),
        cfg.densities.size(), r.seconds);
    return 0;
}

// ---- saturation: the frames' measurement (camera/frame_saturation.hpp) ----

struct SatArgs {
    std::vector<std::string> inputs, rects, polygons;
    std::string out, ids, scene, timestamps, prefix = "target_", bag, topic;
    double fps = 0;
};

int runSaturation(const SatArgs& a)
{
    SaturationRunConfig cfg{a.inputs, a.bag,    a.topic,      a.rects, a.polygons, a.ids,
                            a.scene,  a.prefix, a.timestamps, a.fps,   {}};
    frameRegions(a.rects, a.polygons);  // the patches' errors first, as they were
    RunFiles files;
    if (a.bag.empty()) {
        if (!a.inputs.empty())
            for (const auto& f : listFrames(a.inputs)) files.input(f, "the frames");
        if (!a.ids.empty())
            for (const auto& f : listFrames({a.ids})) files.input(f, "--ids");
        files.input(a.timestamps, "--timestamps");
    } else {
        bagInputs(files, a.bag, "--bag");
    }
    files.output(a.out, "--out");
    cfg.on_scene = [&](const Scene& scene) { recordSceneInputs(files, a.scene, scene); };
    const SaturationSeries s = runSaturation(cfg);
    writeSaturationCsv(files.stage(a.out), s);
    files.commit();
    if (a.bag.empty())
        say("wrote %s (%zu frames, patches: %zu)\n", a.out.c_str(), s.time_s.size(), s.patch_names.size());
    else
        say("wrote %s (%zu frames of %s, patches: %zu)\n", printable(a.out).c_str(), s.time_s.size(),
            printable(s.path).c_str(), s.patch_names.size());
    return 0;
}

}  // namespace

void addCalibration(CLI::App& app, Runner& run)
{
    auto a = std::make_shared<CalibArgs>();
    auto* c = app.add_subcommand(
        "calibrate", "Density ↔ saturation calibration (the paper's Fig. 7) from rendered frames, fitted with Ceres");
    c->add_option("scene", a->scene, "Built-in scene name or scene file")->capture_default_str();
    c->add_option("--densities", a->densities, "Comma-separated densities (default: 14 from 0 to 0.012)");
    c->add_option("--spp", a->cfg.field.batch_spp, "Samples per target pixel in one batch")
        ->capture_default_str()
        ->check(intRange(1, limits::kSpp));
    c->add_option("--rel-error", a->cfg.field.rel_error,
                  "Batches until each patch's fitted radiance has this relative standard error")
        ->capture_default_str()
        ->check(finite())
        ->check(range(1e-4, 1.0));
    c->add_option("--max-batches", a->cfg.field.max_batches, "At most this many batches")
        ->capture_default_str()
        ->check(intRange(4, 4096));
    c->add_option("--width", a->cfg.width, "Frame width [px]")
        ->capture_default_str()
        ->check(intRange(1, limits::kFrameSide));
    c->add_option("--height", a->cfg.height, "Frame height [px]")
        ->capture_default_str()
        ->check(intRange(1, limits::kFrameSide));
    c->add_option("--seed", a->cfg.seed, "Render seed")->transform(seedRule())->capture_default_str();
    c->add_option("--camera", a->cfg.camera, "Scene camera (default: the first)");
    c->add_option("--target-prefix", a->cfg.target_prefix, "Surface-name prefix of the target's patches")
        ->capture_default_str()
        ->check(nonEmpty());
    addChoice(c, "--loss", a->cfg.fit.loss,
              {{"none", RobustLoss::None}, {"huber", RobustLoss::Huber}, {"cauchy", RobustLoss::Cauchy}},
              "Robust loss of the curve fit, default huber");
    c->add_option("--out", a->out, "Calibration JSON to write (e.g. calib/bocas.json)")->required();
    c->add_option("--plot", a->plot, "Also write the plot (PNG)");
    c->callback([a, &run] { run = [a] { return runCalibrate(*a); }; });

    auto s = std::make_shared<SatArgs>();
    auto* t = app.add_subcommand("saturation", "Target HSV saturation of camera frames (files or a folder) → CSV");
    t->add_option("inputs", s->inputs, "Image files or a folder of frames");
    t->add_option("--bag", s->bag, "Or a bag (rosbag2 folder, .mcap, ROS 1 .bag) whose Image topic holds the frames")
        ->check(nonEmpty());
    t->add_option("--topic", s->topic, "The bag's sensor_msgs/Image topic (default: its only one)")->check(nonEmpty());
    t->add_option("--out", s->out, "CSV to write: time_s,saturation,... per-patch columns")->required();
    t->add_option("--rect", s->rects, "A patch: NAME=x,y,width,height in pixels (repeatable)");
    t->add_option("--polygon", s->polygons, "A patch: NAME=x1,y1,x2,y2,x3,y3,... in pixels (repeatable)");
    t->add_option("--ids", s->ids, "Id AOV image(s) from `smokescan render --ids` (file or folder, one per frame)");
    t->add_option("--scene", s->scene, "Scene whose surfaces the ids name");
    t->add_option("--target-prefix", s->prefix, "Surface-name prefix of the target's patches")
        ->capture_default_str()
        ->check(nonEmpty());
    t->add_option("--timestamps", s->timestamps, "Times: lines 'file,time_s' or one time per frame in name order");
    t->add_option("--fps", s->fps, "Frame rate: the number in a file name is a frame index")->check(positive());
    t->callback([s, &run] { run = [s] { return runSaturation(*s); }; });
}

}  // namespace smokescan::cli
