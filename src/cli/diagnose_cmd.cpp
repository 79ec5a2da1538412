// `smokescan diagnose`: a recorded run replayed through the simulation, what the simulation gets
// wrong, the cause, the extended model and its gain on held-out data (docs/diagnosis.md).
#include <cmath>
#include <cstdio>
#include <memory>
#include <set>

#include "commands.hpp"
#include "progress.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/diagnose/diagnosis.hpp"
#include "smokescan/diagnose/diagnosis_report.hpp"
#include "smokescan/fit/fit_inputs.hpp"
#include "smokescan/fit/omni_fit.hpp"
#include "smokescan/io/atomic_folder.hpp"
#include "smokescan/io/run_files.hpp"
#include "smokescan/sensor_config/sensor_file.hpp"

namespace smokescan::cli {
namespace {

struct DiagnoseArgs {
    FitInputsConfig in;
    std::string unit = "mm", sensor_file, model, out, shape = "reference";
    std::string scans;  ///< the recorded scans' source, for the report: the log, or the bag and its topic
    bool lenient = false;
    ReplayConfig replay;
    DiagnosisConfig diag;
    OmniFitConfig omni;
    std::set<std::string> omni_given;  ///< which of --max-range, --floor-z, --tolerance were given (the omnicam's)
};

/// The diagnosis with a bar per round on a terminal.
DiagnosisResult diagnoseWithProgress(const Replay& replay, DiagnosisConfig dc)
{
    std::unique_ptr<Progress> bar;
    int bar_round = 0;
    dc.progress = [&](int round, int done, int total) {
        if (round != bar_round) {
            bar = std::make_unique<Progress>("diagnose round " + std::to_string(round), "candidates");
            bar_round = round;
        }
        bar->update(done, total);
    };
    return diagnose(replay, dc);
}

/// diagnosis.json and report.md into the folder; the verdict and figures printed once it is committed.
void finishDiagnosis(const DiagnoseArgs& a, AtomicFolder& out, const Replay& replay, const DiagnosisResult& r)
{
    const DiagnosisSources src{a.scans,       a.in.saturation,   a.in.scene,      a.in.calibration,
                               a.sensor_file, a.replay.offset_s, a.replay.block_s};
    writeDiagnosisJson(out.path("diagnosis.json"), r, src);
    writeDiagnosisReport(out.path("report.md"), replay, r, src);
    out.commit();
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

/// The omnicam's log against its truth, from the onset its sensor file holds.
int runDiagnoseOmni(DiagnoseArgs& a, AtomicFolder& out, RunFiles& files)
{
    if (a.sensor_file.empty())
        throw Error("--sensor-type omnicam",
                    "needs --sensor-file: the omnicam's onset, as `smokescan fit --sensor-type omnicam` writes it");
    if (!a.model.empty()) throw Error("--model", "is a laser's; the omnicam is replayed with the paper model");
    const OmniSensorFile file = readOmniSensorFile(a.sensor_file);
    if (!a.in.sensor.empty() && !file.camera.empty() && a.in.sensor != file.camera)
        throw Error("--sensor",
                    "names '" + a.in.sensor + "', but " + a.sensor_file + " is the onset of '" + file.camera + "'");
    // The readings are classed as the onset was fitted: the file's tolerance, range and floor.
    OmniFitConfig omni;
    omni.tolerance_m = file.tolerance_m;
    omni.max_range_m = file.max_range_m;
    omni.floor_z_m = file.floor_z_m;
    const std::pair<const char*, std::pair<double, double>> given[] = {
        {"--tolerance", {a.omni.tolerance_m, omni.tolerance_m}},
        {"--max-range", {a.omni.max_range_m, omni.max_range_m}},
        {"--floor-z", {a.omni.floor_z_m, omni.floor_z_m}}};
    for (const auto& [name, v] : given)
        if (a.omni_given.count(name) && std::abs(v.first - v.second) > 1e-6 * std::max(1.0, std::abs(v.second)))
            throw Error(name, fmt("is %g, but %s was fitted with %g", v.first, a.sensor_file.c_str(), v.second));
    omni.camera = a.in.sensor.empty() ? file.camera : a.in.sensor;
    omni.groups = false;
    const OmniFitInputs o = loadOmniFitInputs(a.in, omni);
    if (o.in.scene) recordSceneInputs(files, a.in.scene, *o.in.scene);
    if (std::isnan(a.replay.offset_s)) a.replay.offset_s = file.extensions.clock_offset_s;
    const Replay replay = replayOmniRun(o, file, a.replay);
    const DiagnosisResult r = diagnoseWithProgress(replay, a.diag);
    OmniSensorFile extended = file;
    extended.camera = o.camera;
    extended.extensions = r.model;
    writeOmniSensorFile(out.path("sensor.toml"), extended,
                        "the omnicam's onset from " + a.sensor_file + " with what `smokescan diagnose` learned from " +
                            a.scans + " (verdict: " + r.verdict + ")");
    finishDiagnosis(a, out, replay, r);
    return 0;
}

int runDiagnose(const DiagnoseArgs& a0)
{
    DiagnoseArgs a = a0;
    a.scans = scansSource(a.in.laser, a.in.bag, a.in.topic);
    RunFiles files;
    files.input(a.in.laser, "--laser");
    bagInputs(files, a.in.bag, "--bag");
    saturationInputs(files, a.in.saturation);
    files.input(a.in.calibration, "--calibration");
    files.input(a.sensor_file, "--sensor-file");
    files.outputFolder(a.out, "--out");
    if (a.in.saturation.empty() && !a.in.patch.empty()) throw Error("--patch", "needs --saturation");
    a.in.read = {parseRangeUnit(a.unit), a.lenient};
    a.replay.shape = smokeShapeOf(a.shape, "--smoke-shape");
    a.in.prefix = a.replay.target_prefix;
    // The folder is checked (and staged) before the work: a taken --out fails at once.
    AtomicFolder out(a.out, "the diagnosis folder", "--out");
    if (recordedSensor(a.in.sensor_type).omnicam()) {
        if (!a.in.bag.empty())
            throw Error("--bag", "holds a laser's scans; the omnicam's log is omnirange's (--laser)");
        return runDiagnoseOmni(a, out, files);
    }
    if (!a.omni_given.empty())
        throw Error("diagnose", "--max-range, --floor-z and --tolerance are the omnicam's (--sensor-type omnicam)");
    const FitInputs in = loadFitInputs(a.in);
    a.scans = in.sources.laser;  // a bag's with the topic read
    if (in.scene) recordSceneInputs(files, a.in.scene, *in.scene);
    SensorConfig config = in.mount.config;
    if (!a.sensor_file.empty()) applySensorFile(a.sensor_file, config);
    if (!a.model.empty()) config.model = sensorModelOption("--model", a.model);
    // The clock offset a sensor file learned is the default of --offset.
    if (std::isnan(a.replay.offset_s)) a.replay.offset_s = config.extensions.clock_offset_s;
    const Replay replay = replayRun(in, config, a.replay);
    const DiagnosisResult r = diagnoseWithProgress(replay, a.diag);
    SensorConfig extended = config;
    extended.extensions = r.model;
    writeSensorFile(out.path("sensor.toml"), extended,
                    "the " + std::string(sensorModelName(config.model)) + " model of " + a.in.scene +
                        "'s sensor with what `smokescan diagnose` learned from " + a.scans + " (verdict: " + r.verdict +
                        ")");
    finishDiagnosis(a, out, replay, r);
    return 0;
}

}  // namespace

void addDiagnose(CLI::App& app, Runner& run)
{
    auto a = std::make_shared<DiagnoseArgs>();
    auto* c = app.add_subcommand("diagnose",
                                 "Replay a recorded run, name what the simulation gets wrong and measure the extended "
                                 "model's gain on held-out data");
    addScansOptions(c, a->in.laser, a->in.bag, a->in.topic, "Recorded laser log (the paper's format)");
    addSaturationOptions(c, a->in.saturation, a->in.image_topic, a->in.rects, a->in.polygons,
                         "The camera's saturation CSV (drives the replayed smoke; without it the scene's own smoke "
                         "time line is replayed)");
    c->add_option("--scene", a->in.scene, "Scene the run was recorded in (built-in name or file)")->required();
    c->add_option("--out", a->out, "Folder to write (new): diagnosis.json, report.md, sensor.toml")->required();
    c->add_option("--sensor", a->in.sensor, "Sensor in the scene (default: the first of --sensor-type)");
    c->add_option("--sensor-type", a->in.sensor_type,
                  "urg04lx or lms200, or omnicam: the omnirange log against the scene's truth, from the onset of "
                  "--sensor-file (--sensor then names the omni camera)")
        ->capture_default_str();
    addOmniClassOptions(c, a->omni, a->omni_given);
    c->add_option("--sensor-file", a->sensor_file, "Sensor file whose model is diagnosed (default: the scene's)");
    c->add_option("--model", a->model,
                  "Sensor model: paper or physical (the urg04lx's, with --saturation; default: the scene's or the "
                  "sensor file's)");
    c->add_option("--calibration", a->in.calibration, "Density-saturation calibration JSON, or a built-in name")
        ->capture_default_str();
    c->add_option("--patch", a->in.patch, "Use this patch's saturation column and calibration curve");
    c->add_option("--unit", a->unit, "Range unit of the log: mm, cm, m")->capture_default_str();
    c->add_flag("--lenient", a->lenient, "Skip bad lines instead of failing");
    a->replay.offset_s = NAN;
    c->add_option("--offset", a->replay.offset_s,
                  "Camera clock - laser clock [s] (default: the sensor file's clock_offset_s, else 0)")
        ->check(range(-1e5, 1e5));
    c->add_option("--block", a->replay.block_s,
                  "Longest time block of the held-out split [s] (shorter while the smoke changes)")
        ->capture_default_str()
        ->check(positive());
    c->add_option("--smoke-shape", a->shape,
                  "Where the camera's smoke lies along each beam: reference (the scene's densest state, scaled) or "
                  "timeline (the scene's state at each scan, scaled; the paper model only). Without --saturation "
                  "the scene's time line is traced whatever this says")
        ->capture_default_str();
    c->add_option("--camera", a->replay.camera, "Scene camera that saw the target (default: the first)");
    c->add_option("--target-prefix", a->replay.target_prefix, "The camera's target surfaces")
        ->capture_default_str()
        ->check(nonEmpty());
    c->add_option("--alpha", a->diag.alpha, "False-alarm level of each round")
        ->capture_default_str()
        ->check(range(1e-9, 0.5));
    c->add_option("--max-findings", a->diag.max_findings, "Greedy rounds at most")
        ->capture_default_str()
        ->check(intRange(1, 8));
    c->add_option("--seed", a->diag.seed, "Seed of the sign-flip draws")->transform(seedRule())->capture_default_str();
    c->callback([a, &run] { run = [a] { return runDiagnose(*a); }; });
}

}  // namespace smokescan::cli
