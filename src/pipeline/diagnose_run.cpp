#include "smokescan/pipeline/diagnose_run.hpp"

#include <cmath>

#include "smokescan/core/format.hpp"
#include "smokescan/io/atomic_folder.hpp"
#include "watched.hpp"

namespace smokescan {
namespace {

/// The settings a caller chose, bounded before any work (the command line's checks, for callers
/// that are not it).
void checkSettings(const DiagnoseRunConfig& a)
{
    if (!(a.diag.alpha >= 1e-9 && a.diag.alpha <= 0.5)) throw Error("--alpha", "must lie in [1e-9, 0.5]");
    if (a.diag.max_findings < 1 || a.diag.max_findings > 8) throw Error("--max-findings", "must lie in 1…8");
    if (!(a.replay.block_s > 0) || !std::isfinite(a.replay.block_s))
        throw Error("--block", "must be a finite number > 0 [s]");
    if (!std::isnan(a.replay.offset_s) && !(std::abs(a.replay.offset_s) <= 1e5))
        throw Error("--offset", "must lie in [-1e5, 1e5] s");
}

/// Where a diagnosis on another thread leaves its progress, and the caller's stop.
struct Watching {
    const std::atomic<bool>* stop = nullptr;
    std::atomic<long long> done{0}, total{0};
};

/// The diagnosis, its progress left for the watching thread and its stop asked after each candidate.
DiagnosisResult diagnoseUnder(const Replay& replay, DiagnosisConfig dc, Watching& w)
{
    const auto own = dc.progress;
    dc.progress = [&](int round, int done, int total) {
        if (own) own(round, done, total);
        w.done = done, w.total = total;
        if (w.stop && *w.stop) throw Error("diagnose", "stopped");
    };
    return diagnose(replay, dc);
}

/// The omnicam's log against its truth, from the onset its sensor file holds.
void diagnoseOmni(DiagnoseRunConfig& a, DiagnoseRunResult& out, Watching& w)
{
    if (a.sensor_file.empty())
        throw Error("--sensor-type omnicam",
                    "needs --sensor-file: the omnicam's onset, as `smokescan fit --sensor-type omnicam` writes it");
    if (a.model) throw Error("--model", "is a laser's; the omnicam is replayed with the paper model");
    if (!a.in.bag.empty()) throw Error("--bag", "holds a laser's scans; the omnicam's log is omnirange's (--laser)");
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
    OmniFitInputs o = loadOmniFitInputs(a.in, omni);
    if (a.on_scene && o.in.scene) a.on_scene(*o.in.scene);
    if (std::isnan(a.replay.offset_s)) a.replay.offset_s = file.extensions.clock_offset_s;
    out.replay = std::make_unique<Replay>(replayOmniRun(o, file, a.replay));
    out.scene = std::move(o.in.scene);
    out.diagnosis = diagnoseUnder(*out.replay, a.diag, w);
    OmniSensorFile extended = file;
    extended.camera = o.camera;
    extended.extensions = out.diagnosis.model;
    out.omni = extended;
    out.sensor_comment = "the omnicam's onset from " + a.sensor_file + " with what `smokescan diagnose` learned from " +
        out.sources.laser + " (verdict: " + out.diagnosis.verdict + ")";
}

/// The diagnosis, on whichever thread runs it (runDiagnosis watches it from the caller's).
DiagnoseRunResult diagnosisRun(DiagnoseRunConfig a, Watching& w)
{
    DiagnoseRunResult out;
    out.sources.laser = scansSource(a.in.laser, a.in.bag, a.in.topic);
    if (a.in.saturation.empty() && !a.in.patch.empty()) throw Error("--patch", "needs --saturation");
    a.in.prefix = a.replay.target_prefix;
    if (recordedSensor(a.in.sensor_type).omnicam()) {
        diagnoseOmni(a, out, w);
    } else {
        if (!a.omni_given.empty())
            throw Error("diagnose", "--max-range, --floor-z and --tolerance are the omnicam's (--sensor-type omnicam)");
        FitInputs in = loadFitInputs(a.in);
        if (a.on_scene && in.scene) a.on_scene(*in.scene);
        out.sources.laser = in.sources.laser;  // a bag's with the topic read
        SensorConfig config = in.mount.config;
        if (!a.sensor_file.empty()) applySensorFile(a.sensor_file, config);
        if (a.model) config.model = *a.model;
        // The clock offset a sensor file learned is the default of the offset.
        if (std::isnan(a.replay.offset_s)) a.replay.offset_s = config.extensions.clock_offset_s;
        out.replay = std::make_unique<Replay>(replayRun(in, config, a.replay));
        out.scene = std::move(in.scene);
        out.diagnosis = diagnoseUnder(*out.replay, a.diag, w);
        SensorConfig extended = config;
        extended.extensions = out.diagnosis.model;
        out.laser = extended;
        out.sensor_comment = "the " + std::string(sensorModelName(config.model)) + " model of " + a.in.scene +
            "'s sensor with what `smokescan diagnose` learned from " + out.sources.laser +
            " (verdict: " + out.diagnosis.verdict + ")";
    }
    out.sources.saturation = a.in.saturation;
    out.sources.scene = a.in.scene;
    out.sources.calibration = a.in.calibration;
    out.sources.sensor_file = a.sensor_file;
    out.sources.offset_s = a.replay.offset_s;
    out.sources.block_s = a.replay.block_s;
    return out;
}

}  // namespace

DiagnoseRunResult runDiagnosis(DiagnoseRunConfig a, const RunControl& control)
{
    checkSettings(a);
    checkCancel(control);
    Watching w;
    if (!control.cancel && !control.progress) return diagnosisRun(std::move(a), w);
    // On a thread of its own: the replay stopped within a beam's or a time's work, the diagnosis
    // between candidates; progress is each round's candidates.
    RenderWatch watch;
    w.stop = &watch.stop;
    a.replay.stop = &watch.stop;
    return detail::runWatched<DiagnoseRunResult>([&] { return diagnosisRun(a, w); }, watch,
                                                 [&] { return std::pair<long long, long long>(w.done, w.total); },
                                                 control);
}

std::string diagnosisReportJson(const DiagnoseRunResult& r) { return diagnosisJson(r.diagnosis, r.sources); }

void writeDiagnosisFolder(AtomicFolder& out, const DiagnoseRunResult& r)
{
    if (r.laser) writeSensorFile(out.path("sensor.toml"), *r.laser, r.sensor_comment);
    if (r.omni) writeOmniSensorFile(out.path("sensor.toml"), *r.omni, r.sensor_comment);
    writeDiagnosisJson(out.path("diagnosis.json"), r.diagnosis, r.sources);
    writeDiagnosisReport(out.path("report.md"), *r.replay, r.diagnosis, r.sources);
    out.commit();
}

}  // namespace smokescan
