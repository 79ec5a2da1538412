// `smokescan scan`: laser scans of a scene over time, the paper's log, and a summary.
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>

#include "commands.hpp"
#include "progress.hpp"
#include "scan_lidar.hpp"
#include "smokescan/bag/scan_bag.hpp"
#include "smokescan/calib/calibration.hpp"
#include "smokescan/calib/saturation_predict.hpp"
#include "smokescan/camera/frame_folder.hpp"
#include "smokescan/camera/saturation_render.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/io/image.hpp"
#include "smokescan/io/run_files.hpp"
#include "smokescan/lidar/lidar_spec.hpp"
#include "smokescan/pipeline/laser_run.hpp"
#include "smokescan/pipeline/lidar_run.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/sensors/laser_log.hpp"
#include "smokescan/sensors/scan_summary.hpp"
#include "smokescan/sensors/scanner.hpp"

namespace smokescan::cli {
namespace {

struct ScanArgs {
    LidarScanArgs lidar;
    std::string scene = "bocas", out, tau_csv, image, target = "target";
    std::string saturation_out, calibration = "bocas", camera, frames_dir, model, bag;
    SaturationSimConfig sat;
    bool saturation_render = false;
    SaturationRenderConfig render;
    double image_range_m = 0;
    ScanConfig cfg;
    double from = NAN, to = NAN, bin_s = 0;
    bool quiet = false, rate_given = false;
};

struct CameraStream {
    SaturationSeries series;
    std::vector<std::string> header;
};

/// The camera's saturation over the scan times: predicted, or measured in rendered frames (kept in
/// `frames` when given), on the camera's clock.
CameraStream cameraStream(const Scene& scene, const ScanArgs& a, const std::vector<double>& times,
                          const SaturationPredictor* predictor, const SaturationRenderer* renderer, FrameFolder* frames,
                          ScanBag* bag)
{
    if (times.empty()) throw Error("--saturation-out", "no scan times to cover");
    SaturationSimConfig ss = a.sat;
    ss.from_s = times.front();
    ss.to_s = times.back();
    ss.seed = a.cfg.seed;
    const std::string cam = a.camera.empty() ? "(first)" : a.camera;
    char h[320];
    CameraStream out;
    if (renderer) {
        std::snprintf(
            h, sizeof h,
            "camera %s, target '%s*': rendered frames %dx%d, %d spp, auto exposure; noise sigma %g; camera clock = scene clock + %g s",
            cam.c_str(), a.target.c_str(), a.render.width, a.render.height, a.render.field.batch_spp, ss.sigma,
            ss.clock_offset_s);
        const Progress progress("rendering", "camera frames");
        const long long total = (long long)std::floor((ss.to_s - ss.from_s) * ss.rate_hz + 1e-9) + 1;
        out.series = simulateSaturation(
            [&](double t, uint64_t k) {
                Image display, ids;
                const bool keep = frames || bag;
                const TargetSaturation m = renderer->measure(t, k, keep ? &display : nullptr, keep ? &ids : nullptr);
                if (frames) frames->add(k, t + ss.clock_offset_s, display, ids);
                if (bag) bag->addImage(display, t + ss.clock_offset_s, t, *scene.findCamera(renderer->cameraName()));
                progress.update((long long)k + 1, total);
                SaturationFrame f{m.all.mean, {}};
                for (const auto& [name, p] : m.patches) f.patches[name] = p.mean;
                return f;
            },
            ss);
    } else {
        std::snprintf(
            h, sizeof h,
            "camera %s looking at '%s*' over %.3f m; calibration %s; noise sigma %g; camera clock = scene clock + %g s",
            cam.c_str(), a.target.c_str(), predictor->path_m(), a.calibration.c_str(), ss.sigma, ss.clock_offset_s);
        out.series = simulateSaturation(scene, *predictor, ss);
    }
    out.header = {"smokescan scan " + scene.source + (renderer ? ": rendered" : ": predicted") + " target saturation",
                  h};
    return out;
}

/// The log's header: the scene, the sensor and its model's smoke parameter, the format.
std::vector<std::string> logHeader(const Scene& scene, const Scanner& sc, const ScanArgs& a)
{
    // The model's own smoke parameter: the paper's penetration power, or the receiver's noise floor.
    char buf[256];
    std::snprintf(buf, sizeof buf, "sensor=%s type=%s model=%s %s rate_hz=%g seed=%llu", sc.mount().name.c_str(),
                  sensorTypeName(sc.spec().type), sensorModelName(sc.mount().config.model),
                  sc.model().smokeParameter().c_str(), a.cfg.rate_hz, (unsigned long long)a.cfg.seed);
    return {"smokescan scan " + scene.source, buf,
            "format: time_s then pairs of (angle_rad, range_mm); error codes: " + sc.spec().errorValueSummary()};
}

/// Every file the run reads and writes, checked against each other before any work.
void recordFiles(RunFiles& files, const ScanArgs& a)
{
    files.input(a.cfg.sensor_file, "--sensor-file");
    files.input(a.calibration, "--calibration");
    files.output(a.out, "--out");
    files.output(a.tau_csv, "--tau");
    files.output(a.image, "--image");
    files.output(a.saturation_out, "--saturation-out");
    files.outputFolder(a.frames_dir, "--saturation-frames");
    files.outputFolder(a.bag, "--bag");
}

/// The options only a 3D lidar takes, and whether each was given.
std::vector<std::pair<bool, const char*>> lidarOnly(const ScanArgs& a)
{
    return {{!a.lidar.points_dir.empty(), "--points"},
            {a.lidar.returns_given, "--returns"},
            {a.lidar.format != "pcd", "--points-format"},
            {a.lidar.columns > 0, "--columns"},
            {!a.lidar.range_image.empty(), "--range-image"},
            {!a.lidar.top_view.empty(), "--top-view"},
            {a.lidar.top_view_m != LidarScanArgs{}.top_view_m, "--top-view-width"}};
}

/// A scan with a 3D lidar: the 2D lasers' options refused, the rest handed over.
int scanLidar(const Scene& scene, const ScanArgs& a)
{
    const std::vector<std::pair<bool, const char*>> laser_only = {
        {!a.out.empty(), "--out"},
        {!a.tau_csv.empty(), "--tau"},
        {!a.image.empty(), "--image"},
        {!a.model.empty(), "--model"},
        {!a.cfg.sensor_file.empty(), "--sensor-file"},
        {a.cfg.penetration_power > 0, "--penetration-power"},
        {!a.saturation_out.empty(), "--saturation-out"},
        {a.saturation_render, "--saturation-render"},
        {!a.frames_dir.empty(), "--saturation-frames"},
        {a.image_range_m > 0, "--image-range"},
        {a.bin_s > 0, "--bin"},
        {a.target != ScanArgs{}.target, "--target"},
        {!a.camera.empty(), "--camera"},
        {a.calibration != ScanArgs{}.calibration, "--calibration"},
        {a.sat.rate_hz != SaturationSimConfig{}.rate_hz, "--saturation-rate"},
        {a.sat.sigma != SaturationSimConfig{}.sigma, "--saturation-sigma"},
        {a.render.width != SaturationRenderConfig{}.width, "--saturation-width"},
        {a.render.height != SaturationRenderConfig{}.height, "--saturation-height"},
        {a.render.field.batch_spp != SaturationRenderConfig{}.field.batch_spp, "--saturation-spp"},
        {!std::isnan(a.sat.clock_offset_s), "--camera-offset"}};
    for (const auto& [given, option] : laser_only)
        if (given)
            throw Error(option, "is for the 2D lasers; the " + a.cfg.sensor + " writes point clouds (--points DIR)");
    LidarScanArgs l = a.lidar;
    l.scene = a.scene;
    l.sensor = a.cfg.sensor;
    l.rate_hz = a.rate_given ? a.cfg.rate_hz : 0;
    l.from = a.from;
    l.to = a.to;
    l.seed = a.cfg.seed;
    l.bag = a.bag;
    return runLidarScan(scene, l);
}

int runScan(const ScanArgs& a0)
{
    ScanArgs a = a0;
    const Scene scene = loadScene(a.scene);
    if (isLidarRun(scene, a.cfg.sensor)) return scanLidar(scene, a);
    RunFiles files;
    recordSceneInputs(files, a.scene, scene);
    recordFiles(files, a);
    if (!a.image.empty() && !isImageExtension(a.image))
        throw Error(a.image, "unknown image format (png, exr, jpg, tif)");
    if (!std::isnan(a.from)) a.cfg.from_s = a.from;
    if (!std::isnan(a.to)) a.cfg.to_s = a.to;
    if (!a.model.empty()) a.cfg.model = sensorModelOption("--model", a.model);
    const LaserRun scan_run(scene, a.cfg);  // an unknown sensor is named before anything else
    const Scanner& sc = scan_run.scanner();
    const SurfaceSet& surfaces = scan_run.surfaces();
    for (const auto& [given, option] : lidarOnly(a))
        if (given) throw Error(option, "is for a 3D lidar (--sensor vlp16, hdl32e, os1-128 or a preset file)");
    if (a.out.empty() && a.bag.empty())
        throw Error("--out", "a 2D laser's scans need a log or a bag to go to (--out FILE, --bag DIR)");
    // The clock offset a sensor file learned (smokescan diagnose) is the default of --camera-offset.
    if (std::isnan(a.sat.clock_offset_s)) a.sat.clock_offset_s = sc.mount().config.extensions.clock_offset_s;
    const std::vector<double>& times = scan_run.times();
    if (!a.image.empty() && (long long)times.size() > limits::kImageScans)
        throw Error("--image",
                    "would draw " + std::to_string(times.size()) + " scans (at most " +
                        std::to_string(limits::kImageScans) + "; draw a shorter span or a lower --rate)");
    if (!a.saturation_out.empty() && !times.empty()) {
        const double frames_wanted = (times.back() - times.front()) * a.sat.rate_hz + 1;
        if (frames_wanted > double(limits::kFrames))
            throw Error("--saturation-rate",
                        "would make " + limits::count(std::floor(frames_wanted)) + " camera frames (at most " +
                            std::to_string(limits::kFrames) + ")");
        const TargetRadianceConfig& f = a.render.field;  // the worst case: every batch
        if (a.saturation_render &&
            double(a.render.width) * a.render.height * (f.meter_spp + double(f.max_batches) * f.batch_spp) >
                double(limits::kFrameSamples))
            throw Error("--saturation-spp",
                        "width × height × spp × " + std::to_string(f.max_batches) + " batches is over " +
                            std::to_string(limits::kFrameSamples) + " samples a frame");
    }
    if (a.saturation_render && a.saturation_out.empty()) throw Error("--saturation-render", "needs --saturation-out");
    if (!a.frames_dir.empty() && !a.saturation_render) throw Error("--saturation-frames", "needs --saturation-render");
    std::unique_ptr<FrameFolder> frames;
    if (!a.frames_dir.empty()) frames = std::make_unique<FrameFolder>(a.frames_dir);
    // The camera's stream, checked before the scans are made.
    std::unique_ptr<SaturationPredictor> predictor;
    std::unique_ptr<SaturationRenderer> renderer;
    if (!a.saturation_out.empty() && a.saturation_render) {
        SaturationRenderConfig rc = a.render;
        rc.camera = a.camera;
        rc.target_prefix = a.target + "_";
        rc.seed = a.cfg.seed;
        renderer = std::make_unique<SaturationRenderer>(scene, surfaces, rc, times.empty() ? 0.0 : times.front());
    } else if (!a.saturation_out.empty()) {
        predictor = std::make_unique<SaturationPredictor>(scene, surfaces, readCalibrationJson(a.calibration).curve,
                                                          a.camera, a.target + "_");
    }
    // Scans are streamed to the outputs' temporaries: memory does not grow with the run's length
    // (only --image keeps each scan's values, within limits::kImageScans).
    ScanSummary summary(scene, sc, a.target, a.bin_s, times, a.quiet ? 0 : limits::kSummaryRows);
    std::unique_ptr<AtomicFile> log;
    if (!a.out.empty()) {
        log = std::make_unique<AtomicFile>(files.stage(a.out));
        writeLaserLogHeader(log->stream(), logHeader(scene, sc, a));
    }
    std::unique_ptr<ScanBag> bag;
    if (!a.bag.empty()) bag = std::make_unique<ScanBag>(a.bag, scene);
    std::unique_ptr<AtomicFile> tau;
    if (!a.tau_csv.empty()) {
        tau = std::make_unique<AtomicFile>(files.stage(a.tau_csv));
        writeBeamCsvHeader(tau->stream());
    }
    std::vector<Scan> drawn;  // values only, for --image
    scan_run.run([&](Scan&& s) {
        if (log) writeLaserLogScan(log->stream(), s, sc.spec());
        if (bag) bag->add(s, sc.spec(), sc.mount());
        if (tau) writeBeamCsvScan(tau->stream(), s, scene);
        summary.add(s);
        if (!a.image.empty()) drawn.push_back(Scan{s.time_s, {}, std::move(s.value), {}});
    });
    if (log) log->commit();
    if (tau) tau->commit();
    if (!a.image.empty())
        writeScanImage(files.stage(a.image), drawn, sc.spec(),
                       a.image_range_m > 0 ? a.image_range_m : sc.spec().range_max_m);
    if (!a.saturation_out.empty()) {
        const CameraStream stream =
            cameraStream(scene, a, times, predictor.get(), renderer.get(), frames.get(), bag.get());
        writeSaturationCsv(files.stage(a.saturation_out), stream.series, stream.header);
    }
    if (bag) bag->finish();
    files.commit([&] {
        if (frames) frames->commit();
        if (bag) bag->commit();
    });
    if (!a.quiet) say("%s", summary.text().c_str());
    say("wrote %s (%zu scans)%s%s%s%s%s%s%s%s\n", (a.out.empty() ? a.bag : a.out).c_str(), times.size(),
        a.out.empty() || a.bag.empty() ? "" : ", ", a.out.empty() ? "" : a.bag.c_str(), a.tau_csv.empty() ? "" : ", ",
        a.tau_csv.c_str(), a.image.empty() ? "" : ", ", a.image.c_str(), a.saturation_out.empty() ? "" : ", ",
        a.saturation_out.c_str());
    return 0;
}

}  // namespace

void addScan(CLI::App& app, Runner& run)
{
    auto a = std::make_shared<ScanArgs>();
    auto* c = app.add_subcommand("scan", "Simulate laser scans of a scene over time; write the paper's log format");
    c->add_option("scene", a->scene, "Built-in scene name or scene file (.toml)")->capture_default_str();
    c->add_option("--sensor", a->cfg.sensor,
                  "Sensor name or type in the scene (urg04lx, lms200), or a 3D lidar preset (vlp16, hdl32e, os1-128) "
                  "or preset file (.toml) mounted where the scene's first sensor is; default: the scene's first");
    c->add_option("--from", a->from, "First scan time [s] (default: scene start)")->check(finite());
    c->add_option("--to", a->to, "Last scan time [s] (default: scene end)")->check(finite());
    c->add_option("--rate", a->cfg.rate_hz, "Scans per second [Hz]; a 3D lidar's spin rate (default: its preset's)")
        ->capture_default_str()
        ->check(positive())
        ->each([a](const std::string&) { a->rate_given = true; });
    c->add_option("--points", a->lidar.points_dir,
                  "3D lidar: a new folder for one point cloud per frame (000000.pcd, ...), fields x y z intensity ring "
                  "return_index time source");
    c->add_option("--points-format", a->lidar.format, "3D lidar: pcd (binary) or ply (binary)")->capture_default_str();
    c->add_option("--returns", a->lidar.returns, "3D lidar: which echoes become points: first, last, strongest or dual")
        ->capture_default_str()
        ->each([a](const std::string&) { a->lidar.returns_given = true; });
    c->add_option("--columns", a->lidar.columns, "3D lidar: columns a turn, among those its preset offers")
        ->check(intRange(1, 8192));
    c->add_option("--range-image", a->lidar.range_image,
                  "3D lidar: the first frame's range image (PNG): a row per channel, orange where smoke returned");
    c->add_option("--top-view", a->lidar.top_view,
                  "3D lidar: the first frame's points from above (PNG): surfaces grey, smoke echoes orange");
    c->add_option("--top-view-width", a->lidar.top_view_m, "3D lidar: half the top view's width [m]")
        ->capture_default_str()
        ->check(range(0.1, 1e4));
    c->add_option("--out", a->out, "Laser log to write (2D lasers)");
    c->add_option("--bag", a->bag,
                  "Also (or instead of --out, --points) a ROS 2 bag, a new folder: metadata.yaml and an MCAP file "
                  "with /scan (sensor_msgs/LaserScan) or a 3D lidar's /points (PointCloud2), /tf and /tf_static "
                  "(docs/bags.md)")
        ->check(nonEmpty());
    c->add_option("--tau", a->tau_csv, "Also write per-beam optical depth and columns (CSV)");
    c->add_option(
        "--image", a->image,
        "Also draw the scan series as the paper's Fig. 10 (PNG): angle across, time down, shade = range, red = error");
    c->add_option("--image-range", a->image_range_m, "Range [m] drawn white in --image (default: the sensor's maximum)")
        ->check(positive());
    c->add_option("--model", a->model, "Sensor model: paper or physical (default: the scene's or sensor file's)");
    c->add_option("--sensor-file", a->cfg.sensor_file,
                  "Sensor file (TOML) with the model and its parameters (docs/sensors.md)");
    c->add_option("--penetration-power", a->cfg.penetration_power, "Paper model penetration power [density·m]")
        ->check(positive());
    c->add_option("--seed", a->cfg.seed, "Noise seed")->transform(seedRule())->capture_default_str();
    c->add_option("--target", a->target, "Surface-name prefix the summary counts as the target")
        ->capture_default_str()
        ->check(nonEmpty());
    c->add_option("--bin", a->bin_s, "Summary time bin [s] (default: automatic)")->check(positive());
    c->add_flag("--quiet", a->quiet, "No summary");
    c->add_option(
        "--saturation-out", a->saturation_out,
        "Also write the camera's target saturation over time (CSV), predicted from the smoke on its line of sight");
    c->add_flag("--saturation-render", a->saturation_render,
                "Measure --saturation-out in rendered camera frames instead (slow: 2–3 s per 320x240 frame)");
    c->add_option("--saturation-spp", a->render.field.batch_spp,
                  "Samples per target pixel in one batch of those frames")
        ->capture_default_str()
        ->check(intRange(1, limits::kSpp));
    c->add_option("--saturation-width", a->render.width, "Width of those frames [px]")
        ->capture_default_str()
        ->check(intRange(1, limits::kFrameSide));
    c->add_option("--saturation-height", a->render.height, "Height of those frames [px]")
        ->capture_default_str()
        ->check(intRange(1, limits::kFrameSide));
    c->add_option(
        "--saturation-frames", a->frames_dir,
        "Also keep those frames: a new folder of PNG frames, id AOVs (EXR) and timestamps.csv for `smokescan saturation`");
    c->add_option("--calibration", a->calibration,
                  "Density-saturation calibration for the predicted --saturation-out (JSON or built-in name)")
        ->capture_default_str();
    c->add_option("--camera", a->camera, "Scene camera for --saturation-out (default: the first)");
    c->add_option("--saturation-rate", a->sat.rate_hz, "Camera frames per second for --saturation-out [Hz]")
        ->capture_default_str()
        ->check(positive());
    c->add_option("--saturation-sigma", a->sat.sigma, "Measurement noise added to the saturation (standard deviation)")
        ->capture_default_str()
        ->check(nonnegative())
        ->check(range(0.0, 1.0));
    a->sat.clock_offset_s = NAN;
    c->add_option("--camera-offset", a->sat.clock_offset_s,
                  "Camera clock - laser clock [s] in --saturation-out, within +/-1e5 s as in a sensor file "
                  "(default: the sensor file's clock_offset_s, else 0)")
        ->check(range(-1e5, 1e5));
    c->callback([a, &run] { run = [a] { return runScan(*a); }; });
}

}  // namespace smokescan::cli
