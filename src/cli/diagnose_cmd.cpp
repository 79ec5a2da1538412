// `smokescan diagnose`: a recorded run replayed through the simulation, what the simulation gets
// wrong, the cause, the extended model and its gain on held-out data (docs/diagnosis.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <set>

#include "commands.hpp"
#include "progress.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/io/atomic_folder.hpp"
#include "smokescan/io/run_files.hpp"
#include "smokescan/pipeline/diagnose_run.hpp"
#include "smokescan/pipeline/lidar_diagnose_run.hpp"

namespace smokescan::cli {
namespace {

struct DiagnoseArgs {
    DiagnoseRunConfig run;
    std::string unit = "mm", model, out, shape = "reference";
    bool lenient = false;
    LidarDiagnoseRunConfig lidar;  ///< --points: a 3D lidar's frames
};

/// A 3D lidar's frames (--points): the 2D runs' options refused, the lidar's diagnosed.
int diagnoseLidarFrames(const DiagnoseArgs& a0)
{
    DiagnoseArgs a = a0;
    LidarDiagnoseRunConfig& cfg = a.lidar;
    cfg.scene = a.run.in.scene;
    cfg.sensor.sensor = a.run.in.sensor;
    if (cfg.sensor.sensor.empty())
        throw Error("--sensor", "names the lidar whose frames --points holds (a preset or a preset file)");
    cfg.diag.level = a.run.diag.alpha;
    cfg.topic = a.run.in.topic;
    RunFiles files;
    lidarFramesInputs(files, cfg.points);
    files.input(cfg.sensor.sensor, "--sensor");
    files.outputFolder(a.out, "--out");
    outsideLidarFrames(a.out, "--out", cfg.points);
    AtomicFolder out(a.out, "the diagnosis folder", "--out");
    cfg.on_scene = [&](const Scene& scene) { recordSceneInputs(files, cfg.scene, scene); };
    Progress bar("diagnose", "frames");
    RunControl control;
    control.progress = [&](long long done, long long total) { bar.update(done, total); };
    const LidarDiagnoseRunResult r = runLidarDiagnosis(cfg, control);
    writeLidarDiagnosisFolder(out, r);
    const LidarDiagnosis& d = r.diagnosis;
    say("verdict: %s\n", d.verdict.c_str());
    for (const LidarFinding& f : d.tried) {
        if (!f.named) continue;
        say("  %s on %s: %s %+.4g +/- %.2g%s;", lidarCauseName(f.cause), lidarFindingTarget(d, f).c_str(),
            f.cause == LidarCause::BiasedChannel ? "range bias" : "share", f.effect, f.effect_se,
            f.cause == LidarCause::BiasedChannel ? " m" : "");
        say(" held-out gain %.4g nats, p = %.2g\n", f.gain_nats, f.p_value);
    }
    long long missed = 0;
    for (const LidarGroupStats& g : d.rings) missed += g.missed;
    auto tidy = [](double v) { return std::abs(v) < 1e-9 ? 0.0 : v; };
    say("%zu frames, %lld clear beams compared, %.2f %% of them unanswered; %lld points matched no beam; ", d.frames,
        d.clear, d.clear ? 100.0 * double(missed) / double(d.clear) : 0.0, d.unmatched_points);
    if (d.empty_frames > 0) say("%zu empty frame%s left out; ", d.empty_frames, d.empty_frames == 1 ? "" : "s");
    if (std::isnan(d.pose_mismatch_m))
        say("no recorded poses (a bag's frames: the scene's taken)\n");
    else
        say("recorded poses within %.3g m and %.3g deg of the scene's\n", tidy(d.pose_mismatch_m),
            tidy(d.pose_mismatch_deg));
    say("wrote %s/diagnosis.json, %s/report.md and %s/lidar.toml (the preset extended by what was named)\n",
        a.out.c_str(), a.out.c_str(), a.out.c_str());
    return 0;
}

/// The verdict and figures, printed once the folder is committed.
void sayDiagnosis(const DiagnoseArgs& a, const DiagnosisResult& r)
{
    say("verdict: %s\n", r.verdict.c_str());
    if (r.shape == SmokeShape::Reference && r.shape_error_ln >= kShapeWarningLn)
        say("warning: the scene's smoke changes shape (its densest state misstates the beams' columns by %.2f in "
            "ln): the estimates are attenuated; --smoke-shape timeline if the scene's time line is right\n",
            r.shape_error_ln);
    for (const auto& f : r.findings) {
        say("  %s%s%s:", f.cause.c_str(), f.target.empty() ? "" : " on ", f.target.c_str());
        for (const auto& [name, e] : f.parameters) say(" %s = %.5g +/- %.2g;", name.c_str(), e.value, e.se);
        say(" held-out gain %.4g nats, p = %.2g\n", f.loglik_gain, f.p_value);
    }
    const ModelFigures& b = r.baseline.front();
    const ModelFigures& e = r.extended.front();
    say("log-likelihood per beam %.4f -> %.4f (held out); missed errors %.3f -> %.3f; invented %.3f -> %.3f\n",
        b.loglik_per_beam, e.loglik_per_beam, b.missed_error_rate, e.missed_error_rate, b.invented_error_rate,
        e.invented_error_rate);
    say("wrote %s/diagnosis.json, %s/report.md and %s/sensor.toml\n", a.out.c_str(), a.out.c_str(), a.out.c_str());
}

/// The options a 3D lidar's diagnosis takes; --returns, --columns and --rate are its alone.
const std::set<std::string> kLidarDiagnoseOptions = {"--points",  "--scene", "--out",   "--sensor", "--returns",
                                                     "--columns", "--rate",  "--alpha", "--topic"};

/// @param given the options given on the command line
int runDiagnose(const DiagnoseArgs& a0, const std::vector<std::string>& given)
{
    if (lidarRun(given, kLidarDiagnoseOptions, "diagnosis")) return diagnoseLidarFrames(a0);
    DiagnoseArgs a = a0;
    FitInputsConfig& in = a.run.in;
    scansSource(in.laser, in.bag, in.topic);
    RunFiles files;
    files.input(in.laser, "--laser");
    bagInputs(files, in.bag, "--bag");
    saturationInputs(files, in.saturation);
    files.input(in.calibration, "--calibration");
    files.input(a.run.sensor_file, "--sensor-file");
    files.outputFolder(a.out, "--out");
    in.read = {parseRangeUnit(a.unit), a.lenient};
    a.run.replay.shape = smokeShapeOf(a.shape, "--smoke-shape");
    if (!a.model.empty()) a.run.model = sensorModelOption("--model", a.model);
    // The folder is checked (and staged) before the work: a taken --out fails at once.
    AtomicFolder out(a.out, "the diagnosis folder", "--out");
    // A bar per round on a terminal.
    std::unique_ptr<Progress> bar;
    int bar_round = 0;
    a.run.diag.progress = [&](int round, int done, int total) {
        if (round != bar_round) {
            bar = std::make_unique<Progress>("diagnose round " + std::to_string(round), "candidates");
            bar_round = round;
        }
        bar->update(done, total);
    };
    a.run.on_scene = [&](const Scene& scene) { recordSceneInputs(files, in.scene, scene); };
    const DiagnoseRunResult r = runDiagnosis(a.run);
    writeDiagnosisFolder(out, r);
    sayDiagnosis(a, r.diagnosis);
    return 0;
}

}  // namespace

void addDiagnose(CLI::App& app, Runner& run)
{
    auto a = std::make_shared<DiagnoseArgs>();
    auto* c = app.add_subcommand("diagnose",
                                 "Replay a recorded run, name what the simulation gets wrong and measure the extended "
                                 "model's gain on held-out data");
    addScansOptions(c, a->run.in.laser, a->run.in.bag, a->run.in.topic, "Recorded laser log (the paper's format)");
    addSaturationOptions(c, a->run.in.saturation, a->run.in.image_topic, a->run.in.rects, a->run.in.polygons,
                         "The camera's saturation CSV (drives the replayed smoke; without it the scene's own smoke "
                         "time line is replayed)");
    c->add_option(
        "--points", a->lidar.points,
        "Or a 3D lidar's frames: a folder as `scan --points` writes it (frames.csv, a PCD or PLY a frame, "
        "with ring and time fields) or a ROS 2 or ROS 1 bag of PointCloud2 frames (--topic); --sensor names the "
        "lidar");
    c->add_option("--returns", a->lidar.sensor.returns, "3D lidar: the frames' return mode (default: the preset's)");
    c->add_option("--columns", a->lidar.sensor.columns, "3D lidar: columns a turn (default: the preset's)")
        ->check(positive());
    c->add_option("--rate", a->lidar.sensor.rate_hz, "3D lidar: spin rate [Hz] (default: the preset's)")
        ->check(positive());
    c->add_option("--scene", a->run.in.scene, "Scene the run was recorded in (built-in name or file)")->required();
    c->add_option("--out", a->out, "Folder to write (new): diagnosis.json, report.md, sensor.toml")->required();
    c->add_option("--sensor", a->run.in.sensor,
                  "Sensor in the scene (default: the first of --sensor-type); with --points the lidar: a preset's name "
                  "(vlp16, hdl32e, os1-128) or a preset file");
    c->add_option("--sensor-type", a->run.in.sensor_type,
                  "urg04lx or lms200, or omnicam: the omnirange log against the scene's truth, from the onset of "
                  "--sensor-file (--sensor then names the omni camera)")
        ->capture_default_str();
    addOmniClassOptions(c, a->run.omni, a->run.omni_given);
    c->add_option("--sensor-file", a->run.sensor_file, "Sensor file whose model is diagnosed (default: the scene's)");
    c->add_option("--model", a->model,
                  "Sensor model: paper or physical (the urg04lx's, with --saturation; default: the scene's or the "
                  "sensor file's)");
    c->add_option("--calibration", a->run.in.calibration, "Density-saturation calibration JSON, or a built-in name")
        ->capture_default_str();
    c->add_option("--patch", a->run.in.patch, "Use this patch's saturation column and calibration curve");
    c->add_option("--unit", a->unit, "Range unit of the log: mm, cm, m")->capture_default_str();
    c->add_flag("--lenient", a->lenient, "Skip bad lines instead of failing");
    a->run.replay.offset_s = NAN;
    c->add_option("--offset", a->run.replay.offset_s,
                  "Camera clock - laser clock [s] (default: the sensor file's clock_offset_s, else 0)")
        ->check(range(-1e5, 1e5));
    c->add_option("--block", a->run.replay.block_s,
                  "Longest time block of the held-out split [s] (shorter while the smoke changes)")
        ->capture_default_str()
        ->check(positive());
    c->add_option("--smoke-shape", a->shape,
                  "Where the camera's smoke lies along each beam: reference (the scene's densest state, scaled) or "
                  "timeline (the scene's state at each scan, scaled; the paper model only). Without --saturation "
                  "the scene's time line is traced whatever this says")
        ->capture_default_str();
    c->add_option("--camera", a->run.replay.camera, "Scene camera that saw the target (default: the first)");
    c->add_option("--target-prefix", a->run.replay.target_prefix, "The camera's target surfaces")
        ->capture_default_str()
        ->check(nonEmpty());
    c->add_option("--alpha", a->run.diag.alpha, "False-alarm level of each round")
        ->capture_default_str()
        ->check(range(1e-9, 0.5));
    c->add_option("--max-findings", a->run.diag.max_findings, "Greedy rounds at most")
        ->capture_default_str()
        ->check(intRange(1, 8));
    c->add_option("--seed", a->run.diag.seed, "Seed of the sign-flip draws")
        ->transform(seedRule())
        ->capture_default_str();
    c->callback([a, c, &run] {
        std::vector<std::string> given;
        for (const CLI::Option* o : c->get_options())
            if (o->count() > 0) given.push_back(o->get_name());
        run = [a, given] { return runDiagnose(*a, given); };
    });
}

}  // namespace smokescan::cli
