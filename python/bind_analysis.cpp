// smokescan.diagnose (and the other analyses of recorded data): the library's runs
// (pipeline/), their results as Report objects with the JSON reports' fields.
#include <pybind11/stl.h>

#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <tuple>

#include "module_support.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/fit/fit_report.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/io/atomic_folder.hpp"
#include "smokescan/io/text_input.hpp"
#include "smokescan/pipeline/calibrate_run.hpp"
#include "smokescan/pipeline/diagnose_run.hpp"
#include "smokescan/pipeline/fit_run.hpp"
#include "smokescan/pipeline/lidar_diagnose_run.hpp"
#include "smokescan/pipeline/lidar_fit_run.hpp"
#include "smokescan/pipeline/saturation_run.hpp"
#include "smokescan/sensor_config/sensor_file.hpp"

namespace smokescan::python {
namespace {

/// The omnicam's classes (--tolerance, --max-range, --floor-z) from Python's optional keywords.
void omniClasses(OmniFitConfig& omni, std::set<std::string>& given, std::optional<double> tolerance_m,
                 std::optional<double> max_range_m, std::optional<double> floor_z_m)
{
    for (const auto& [value, name, target] : {std::tuple{tolerance_m, "--tolerance", &omni.tolerance_m},
                                              std::tuple{max_range_m, "--max-range", &omni.max_range_m},
                                              std::tuple{floor_z_m, "--floor-z", &omni.floor_z_m}})
        if (value) {
            *target = finiteArg(*value, name);
            given.insert(name);
        }
}

/// A JSON report's text as a smokescan.Report.
py::object reportOf(const std::string& json)
{
    const py::object fields = py::module_::import("json").attr("loads")(json);
    return py::module_::import("smokescan._report").attr("Report")(fields);
}

/// The recorded run's files from Python's arguments (fit, diagnose).
FitInputsConfig inputsConfig(const py::object& scene, const py::object& laser, const py::object& bag,
                             const std::string& topic, const py::object& saturation, const py::object& calibration,
                             const std::string& patch, const std::string& sensor, const std::string& sensor_type,
                             const std::string& unit, bool lenient, bool scene_required = true)
{
    FitInputsConfig in;
    in.scene = pathArg(scene, "--scene", !scene_required);
    in.laser = pathArg(laser, "--laser");
    in.bag = pathArg(bag, "--bag");
    in.topic = topic;
    in.saturation = pathArg(saturation, "--saturation");
    in.calibration = pathArg(calibration, "--calibration", false);
    in.patch = patch;
    in.sensor = sensor;
    in.sensor_type = sensor_type;
    in.read = {parseRangeUnit(unit), lenient};
    return in;
}

/// A whole number given from Python within [lo, hi], else an Error naming the option.
int intIn(long long v, long long lo, long long hi, const char* option)
{
    if (v < lo || v > hi) throw Error(option, "must lie in " + std::to_string(lo) + "…" + std::to_string(hi));
    return int(v);
}

RobustLoss lossArg(const std::string& name)
{
    if (name == "none") return RobustLoss::None;
    if (name == "huber") return RobustLoss::Huber;
    if (name == "cauchy") return RobustLoss::Cauchy;
    throw Error("--loss", "'" + name + "' is not one of none, huber, cauchy");
}

ErrorLink linkArg(const std::string& name)
{
    if (name == "probit") return ErrorLink::Probit;
    if (name == "logistic") return ErrorLink::Logistic;
    throw Error("--link", "'" + name + "' is not one of probit, logistic");
}

/// A new file's path: an existing one is refused (a run never replaces a file it did not make).
std::string newFileArg(const py::object& o, const char* option)
{
    const std::string p = pathArg(o, option);
    if (p.empty()) return p;
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::symlink_status(p, ec).type() != fs::file_type::not_found)
        throw Error(p, "exists; " + std::string(option) + " names a new file");
    const fs::path folder = fs::path(p).parent_path();
    if (!folder.empty() && !fs::is_directory(folder, ec)) throw Error(p, "its folder does not exist");
    return p;
}

void bindFits(py::module_& m)
{
    m.def(
        "fit",
        [](const py::object& scene, const py::object& laser, const py::object& bag, const std::string& topic,
           const py::object& saturation, const py::object& calibration, const std::string& patch,
           const std::string& sensor, const std::string& sensor_type, const std::string& target_prefix,
           const std::vector<std::string>& surfaces, const py::object& surfaces_file, const std::string& model,
           const std::string& unit, bool lenient, double offset_s, bool fixed_offset, double offset_window_s,
           const std::string& link, double smooth_s, long long bootstrap, const std::string& reference,
           const std::string& image_topic, const std::vector<std::string>& rects,
           const std::vector<std::string>& polygons, std::optional<double> tolerance_m,
           std::optional<double> max_range_m, std::optional<double> floor_z_m, const py::object& out,
           py::object progress) {
            FitRunConfig cfg;
            omniClasses(cfg.omni, cfg.omni_given, tolerance_m, max_range_m, floor_z_m);
            cfg.in = inputsConfig(scene, laser, bag, topic, saturation, calibration, patch, sensor, sensor_type, unit,
                                  lenient, false);
            cfg.in.prefix = target_prefix;
            cfg.in.surfaces = surfaces;
            cfg.in.surfaces_file = pathArg(surfaces_file, "--surfaces");
            cfg.in.image_topic = image_topic;
            cfg.in.rects = rects;
            cfg.in.polygons = polygons;
            cfg.model = modelArg(model);
            cfg.fit.offset_s = finiteArg(offset_s, "--offset");
            cfg.fit.estimate_offset = !fixed_offset;
            cfg.fit.offset_window_s = offset_window_s;
            cfg.fit.link = linkArg(link);
            cfg.fit.smooth_s = smooth_s;
            cfg.fit.bootstrap = int(std::clamp<long long>(bootstrap, -1, 1001));
            cfg.fit.reference = reference;
            const std::string file = newFileArg(out, "--out");
            PyControl pc(std::move(progress));
            const std::string json = released(pc, [&](const RunControl& c) {
                const FitRunResult r = runFit(cfg, c);
                if (!r.ok()) throw Error(r.scans, r.failure);
                if (!file.empty() && r.laser) writeSensorFile(file, *r.laser, r.sensor_comment);
                if (!file.empty() && r.omni) writeOmniSensorFile(file, *r.omni, r.sensor_comment);
                return fitRunJson(r);
            });
            return reportOf(json);
        },
        py::arg("scene") = py::none(), py::kw_only(), py::arg("laser") = py::none(), py::arg("bag") = py::none(),
        py::arg("topic") = "", py::arg("saturation") = py::none(), py::arg("calibration") = "bocas",
        py::arg("patch") = "", py::arg("sensor") = "", py::arg("sensor_type") = "urg04lx",
        py::arg("target_prefix") = "target_", py::arg("surfaces") = std::vector<std::string>{},
        py::arg("surfaces_file") = py::none(), py::arg("model") = "paper", py::arg("unit") = "mm",
        py::arg("lenient") = false, py::arg("offset_s") = 0.0, py::arg("fixed_offset") = false,
        py::arg("offset_window_s") = 60.0, py::arg("link") = "probit", py::arg("smooth_s") = 2.0,
        py::arg("bootstrap") = 30, py::arg("reference") = "", py::arg("image_topic") = "",
        py::arg("rects") = std::vector<std::string>{}, py::arg("polygons") = std::vector<std::string>{},
        py::arg("tolerance_m") = py::none(), py::arg("max_range_m") = py::none(), py::arg("floor_z_m") = py::none(),
        py::arg("out") = py::none(), py::arg("progress") = py::none(),
        "`smokescan fit`: a recorded run (laser= log or bag=) and the camera's saturation → the sensor's smoke "
        "thresholds, penetration power and clock offset, by beam groups from the scene (a file or built-in name) or "
        "surfaces=/surfaces_file=. Returns a Report with the fit report's fields (docs/fitting.md); out= also "
        "writes the fitted sensor file (a new TOML file scan(sensor_file=...) reads). A fit that finds no "
        "threshold raises smokescan.Error with the reason");

    m.def(
        "fit_plume",
        [](const py::object& scene, const py::object& laser, const py::object& bag, const std::string& topic,
           const std::string& sensor, const std::string& unit, bool lenient, double time_offset_s, long long bins,
           py::object progress) {
            PlumeRunConfig cfg;
            cfg.scene = pathArg(scene, "--scene", false);
            cfg.laser = pathArg(laser, "--laser");
            cfg.bag = pathArg(bag, "--bag");
            cfg.topic = topic;
            cfg.sensor = sensor;
            cfg.read = {parseRangeUnit(unit), lenient};
            cfg.fit.time_offset_s = time_offset_s;
            cfg.fit.bins = int(std::clamp<long long>(bins, -1, 1 << 30));
            PyControl pc(std::move(progress));
            const std::string json = released(pc, [&](const RunControl& c) {
                const PlumeRunResult r = runPlumeFit(cfg, c);
                if (!r.fit.ok)
                    throw Error(r.source,
                                "no plume penetration could be fitted: " +
                                    (r.fit.diagnoses.empty() ? std::string("no beam crossed a plume")
                                                             : r.fit.diagnoses.front()));
                return plumeFitJson(r.fit, cfg.fit, r.source, cfg.scene);
            });
            return reportOf(json);
        },
        py::arg("scene"), py::kw_only(), py::arg("laser") = py::none(), py::arg("bag") = py::none(),
        py::arg("topic") = "", py::arg("sensor") = "", py::arg("unit") = "mm", py::arg("lenient") = false,
        py::arg("time_offset_s") = 0.0, py::arg("bins") = 8, py::arg("progress") = py::none(),
        "`smokescan fit-plume`: a Sick LMS200's log in a scene with plumes → its penetration depth against the "
        "plumes' density; a Report with the command's JSON fields (docs/fitting.md)");
}

py::array_t<double> doubles(std::vector<double> v) { return ownedArray(std::move(v)); }

/// A saturation series as numpy arrays: the target's and each patch's.
py::dict seriesDict(SaturationSeries&& s)
{
    py::dict d, patches, medians, sds;
    d["time_s"] = doubles(std::move(s.time_s));
    d["saturation"] = doubles(std::move(s.saturation));
    d["median"] = doubles(std::move(s.median));
    d["sd"] = doubles(std::move(s.sd));
    d["pixels"] = doubles(std::move(s.pixels));
    for (size_t p = 0; p < s.patch_names.size(); ++p) {
        const py::str name(s.patch_names[p]);
        patches[name] = doubles(std::move(s.patch[p]));
        if (p < s.patch_median.size()) medians[name] = doubles(std::move(s.patch_median[p]));
        if (p < s.patch_sd.size()) sds[name] = doubles(std::move(s.patch_sd[p]));
    }
    d["patches"] = patches;
    d["patch_median"] = medians;
    d["patch_sd"] = sds;
    return d;
}

/// One path or a list of them (frames: files or folders).
std::vector<std::string> pathsArg(const py::object& o, const char* option)
{
    std::vector<std::string> v;
    if (o.is_none()) return v;
    if (py::isinstance<py::str>(o) || py::isinstance<py::bytes>(o) || py::hasattr(o, "__fspath__"))
        return {pathArg(o, option, false)};
    if (!py::isinstance<py::sequence>(o)) throw Error(option, "must be a path or a list of paths");
    for (const py::handle h : o) v.push_back(pathArg(py::reinterpret_borrow<py::object>(h), option, false));
    return v;
}

void bindSaturation(py::module_& m)
{
    m.def(
        "saturation",
        [](const py::object& frames, const py::object& bag, const std::string& topic,
           const std::vector<std::string>& rects, const std::vector<std::string>& polygons, const py::object& ids,
           const py::object& scene, const std::string& target_prefix, const py::object& timestamps, double fps,
           py::object progress) {
            SaturationRunConfig cfg;
            cfg.inputs = pathsArg(frames, "frames");
            cfg.bag = pathArg(bag, "--bag");
            cfg.topic = topic;
            cfg.rects = rects;
            cfg.polygons = polygons;
            cfg.ids = pathArg(ids, "--ids");
            cfg.scene = pathArg(scene, "--scene");
            cfg.target_prefix = target_prefix;
            cfg.timestamps = pathArg(timestamps, "--timestamps");
            cfg.fps = fps;
            PyControl pc(std::move(progress));
            SaturationSeries s = released(pc, [&](const RunControl& c) { return runSaturation(cfg, c); });
            return seriesDict(std::move(s));
        },
        py::arg("frames") = py::none(), py::kw_only(), py::arg("bag") = py::none(), py::arg("topic") = "",
        py::arg("rects") = std::vector<std::string>{}, py::arg("polygons") = std::vector<std::string>{},
        py::arg("ids") = py::none(), py::arg("scene") = py::none(), py::arg("target_prefix") = "target_",
        py::arg("timestamps") = py::none(), py::arg("fps") = 0.0, py::arg("progress") = py::none(),
        "`smokescan saturation`: the target's HSV saturation on camera frames (files or folders, or bag=), in "
        "rects/polygons (\"NAME=x,y,w,h\", \"NAME=x1,y1,...\" px) or found by ids= (render's id images) with "
        "scene=. A dict of float64 arrays: time_s, saturation, median, sd, pixels (the whole target; the last "
        "three empty when the source gives none), patches, patch_median, patch_sd (dicts by patch name); the "
        "values `smokescan saturation --out` writes");
}

}  // namespace

void bindAnalysis(py::module_& m)
{
    bindFits(m);
    bindSaturation(m);
    m.def(
        "calibrate",
        [](std::shared_ptr<Scene> scene, std::optional<std::vector<double>> densities, long long spp, double rel_error,
           long long max_batches, long long width, long long height, py::object seed, const std::string& camera,
           const std::string& target_prefix, const std::string& loss, py::object progress) {
            CalibrateConfig cfg;
            if (densities) cfg.densities = *densities;
            cfg.field.batch_spp = intIn(spp, 1, limits::kSpp, "--spp");
            if (!(rel_error >= 1e-4 && rel_error <= 1)) throw Error("--rel-error", "must lie in [1e-4, 1]");
            cfg.field.rel_error = rel_error;
            cfg.field.max_batches = intIn(max_batches, 4, 4096, "--max-batches");
            cfg.width = intIn(width, 1, limits::kFrameSide, "--width");
            cfg.height = intIn(height, 1, limits::kFrameSide, "--height");
            cfg.seed = seedArg(seed);
            cfg.camera = camera;
            if (target_prefix.empty()) throw Error("--target-prefix", "must not be empty");
            cfg.target_prefix = target_prefix;
            cfg.fit.loss = lossArg(loss);
            PyControl pc(std::move(progress));
            const std::string json = released(pc, [&](const RunControl& c) {
                return calibrationJson(runCalibration(*scene, cfg, c), cfg, scene->source);
            });
            return reportOf(json);
        },
        py::arg("scene").none(false), py::kw_only(), py::arg("densities") = py::none(), py::arg("spp") = 8,
        py::arg("rel_error") = 0.03, py::arg("max_batches") = 16, py::arg("width") = 320, py::arg("height") = 240,
        py::arg("seed") = 1, py::arg("camera") = "", py::arg("target_prefix") = "target_", py::arg("loss") = "huber",
        py::arg("progress") = py::none(),
        "`smokescan calibrate`: the density-saturation curve (the smoke paper's Fig. 7) from the scene's own "
        "frames at each density (default: 14 from 0 to 0.012), fitted with Ceres. Returns a Report with the "
        "calibration JSON's fields (docs/calibration.md); json.dump(report.to_dict(), f) writes a calibration "
        "that fit and diagnose read. progress(done, total) counts frames");

    m.def(
        "diagnose",
        [](const py::object& scene, const py::object& laser, const py::object& bag, const std::string& topic,
           const py::object& saturation, const py::object& calibration, const std::string& patch,
           const std::string& sensor, const std::string& sensor_type, const py::object& sensor_file,
           std::optional<std::string> model, const std::string& unit, bool lenient, std::optional<double> offset_s,
           double block_s, const std::string& smoke_shape, const std::string& camera, const std::string& target_prefix,
           double alpha, int max_findings, py::object seed, const py::object& out, const std::string& image_topic,
           const std::vector<std::string>& rects, const std::vector<std::string>& polygons,
           std::optional<double> tolerance_m, std::optional<double> max_range_m, std::optional<double> floor_z_m,
           py::object progress) {
            DiagnoseRunConfig cfg;
            cfg.in = inputsConfig(scene, laser, bag, topic, saturation, calibration, patch, sensor, sensor_type, unit,
                                  lenient);
            cfg.in.image_topic = image_topic;
            cfg.in.rects = rects;
            cfg.in.polygons = polygons;
            omniClasses(cfg.omni, cfg.omni_given, tolerance_m, max_range_m, floor_z_m);
            cfg.sensor_file = pathArg(sensor_file, "--sensor-file");
            if (model) cfg.model = modelArg(*model);
            if (offset_s) cfg.replay.offset_s = finiteArg(*offset_s, "--offset");
            cfg.replay.block_s = block_s;
            cfg.replay.shape = smokeShapeOf(smoke_shape, "--smoke-shape");
            cfg.replay.camera = camera;
            if (target_prefix.empty()) throw Error("--target-prefix", "must not be empty");
            cfg.replay.target_prefix = target_prefix;
            cfg.diag.alpha = alpha;
            cfg.diag.max_findings = max_findings;
            cfg.diag.seed = seedArg(seed);
            const std::string folder = pathArg(out, "--out");
            PyControl pc(std::move(progress));
            const std::string json = released(pc, [&](const RunControl& c) {
                // The folder is checked (and staged) before the work: a taken one fails at once.
                std::unique_ptr<AtomicFolder> dir;
                if (!folder.empty()) dir = std::make_unique<AtomicFolder>(folder, "the diagnosis folder", "--out");
                const DiagnoseRunResult r = runDiagnosis(cfg, c);
                if (dir) writeDiagnosisFolder(*dir, r);
                return diagnosisReportJson(r);
            });
            return reportOf(json);
        },
        py::arg("scene"), py::kw_only(), py::arg("laser") = py::none(), py::arg("bag") = py::none(),
        py::arg("topic") = "", py::arg("saturation") = py::none(), py::arg("calibration") = "bocas",
        py::arg("patch") = "", py::arg("sensor") = "", py::arg("sensor_type") = "urg04lx",
        py::arg("sensor_file") = py::none(), py::arg("model") = py::none(), py::arg("unit") = "mm",
        py::arg("lenient") = false, py::arg("offset_s") = py::none(), py::arg("block_s") = 3.0,
        py::arg("smoke_shape") = "reference", py::arg("camera") = "", py::arg("target_prefix") = "target_",
        py::arg("alpha") = 0.05, py::arg("max_findings") = 4, py::arg("seed") = 1, py::arg("out") = py::none(),
        py::arg("image_topic") = "", py::arg("rects") = std::vector<std::string>{},
        py::arg("polygons") = std::vector<std::string>{}, py::arg("tolerance_m") = py::none(),
        py::arg("max_range_m") = py::none(), py::arg("floor_z_m") = py::none(), py::arg("progress") = py::none(),
        "`smokescan diagnose`: a recorded run (laser= log or bag=) replayed in the scene (a file or built-in "
        "name), what the simulation gets wrong, the cause and the extended model's held-out gain. Returns a "
        "Report with diagnosis.json's fields (docs/diagnosis.md); out= also writes the command's folder "
        "(diagnosis.json, report.md, sensor.toml), whole or not at all. A saturation bag's frames are measured "
        "in rects/polygons (\"NAME=x,y,w,h\", \"NAME=x1,y1,...\" px) on image_topic; tolerance_m, max_range_m and "
        "floor_z_m are the omnicam's classes (sensor_type=\"omnicam\"). progress(done, total) counts each round's "
        "candidates");

    m.def(
        "diagnose_lidar",
        [](const py::object& scene, const py::object& points, const std::string& sensor, const std::string& returns,
           int columns, double rate_hz, double alpha, const py::object& out, py::object progress,
           const std::string& topic) {
            LidarDiagnoseRunConfig cfg;
            cfg.scene = pathArg(scene, "scene");
            cfg.points = pathArg(points, "--points");
            cfg.topic = topic;
            if (sensor.empty()) throw Error("--sensor", "names the lidar whose frames points= holds");
            cfg.sensor.sensor = sensor;
            cfg.sensor.returns = returns;
            if (columns < 0) throw Error("--columns", "must be > 0 (0: the preset's)");
            cfg.sensor.columns = columns;
            cfg.sensor.rate_hz = finiteArg(rate_hz, "--rate");
            if (!(alpha >= 1e-9 && alpha <= 0.5)) throw Error("--alpha", "must lie in [1e-9, 0.5]");
            cfg.diag.level = alpha;
            const std::string folder = pathArg(out, "--out");
            PyControl pc(std::move(progress));
            const std::string json = released(pc, [&](const RunControl& c) {
                std::unique_ptr<AtomicFolder> dir;
                if (!folder.empty()) dir = std::make_unique<AtomicFolder>(folder, "the diagnosis folder", "--out");
                const LidarDiagnoseRunResult r = runLidarDiagnosis(cfg, c);
                if (dir) writeLidarDiagnosisFolder(*dir, r);
                return lidarDiagnosisJson(r.diagnosis);
            });
            return reportOf(json);
        },
        py::arg("scene"), py::kw_only(), py::arg("points"), py::arg("sensor"), py::arg("returns") = "",
        py::arg("columns") = 0, py::arg("rate_hz") = 0.0, py::arg("alpha") = 0.05, py::arg("out") = py::none(),
        py::arg("progress") = py::none(), py::arg("topic") = "",
        "`smokescan diagnose --points`: a 3D lidar's recorded frames (points=, a folder as scan --points "
        "writes it, or a ROS 2 bag of PointCloud2 frames on topic=, default its only one) against their replay in the scene: a dropping channel, a dirty-window sector, a biased "
        "channel, smoke echoes taken as first returns, a surface's threshold. Returns a Report with "
        "diagnosis.json's fields (docs/diagnosis.md, \"A 3D lidar's frames\"; extended_preset: the preset "
        "extended by what was named, docs/lidar.md); out= also writes diagnosis.json, report.md and lidar.toml, "
        "whole or not at all. progress(done, total) counts frames");

    m.def(
        "fit_lidar",
        [](const py::object& scene, const py::object& points, const std::string& sensor, const std::string& returns,
           int columns, double rate_hz, const py::object& out, py::object progress, const std::string& topic) {
            LidarFitRunConfig cfg;
            cfg.frames.scene = pathArg(scene, "scene");
            cfg.frames.points = pathArg(points, "--points");
            cfg.frames.topic = topic;
            if (sensor.empty()) throw Error("--sensor", "names the lidar whose frames points= holds");
            cfg.frames.sensor.sensor = sensor;
            cfg.frames.sensor.returns = returns;
            if (columns < 0) throw Error("--columns", "must be > 0 (0: the preset's)");
            cfg.frames.sensor.columns = columns;
            cfg.frames.sensor.rate_hz = finiteArg(rate_hz, "--rate");
            const std::string file = pathArg(out, "--out");
            PyControl pc(std::move(progress));
            const std::string json = released(pc, [&](const RunControl& c) {
                const LidarFitRunResult r = runLidarFit(cfg, c);
                if (!file.empty()) {
                    AtomicFile f(file);
                    f.stream() << r.preset;
                    f.commit();
                }
                return lidarFitJson(r);
            });
            return reportOf(json);
        },
        py::arg("scene"), py::kw_only(), py::arg("points"), py::arg("sensor"), py::arg("returns") = "",
        py::arg("columns") = 0, py::arg("rate_hz") = 0.0, py::arg("out") = py::none(), py::arg("progress") = py::none(),
        py::arg("topic") = "",
        "`smokescan fit --points`: each surface's reflectance factor from a 3D lidar's recorded intensities (points=, "
        "a folder as scan --points writes it, or a ROS 2 bag of PointCloud2 frames on topic=) against their replay in the scene, and the receiver's noise. Returns a "
        "Report with the fit report's fields (docs/lidar.md, \"Fitted from the intensities\"; extended_preset: "
        "the preset extended by the factors); out= also writes that preset. progress(done, total) counts frames");
}

}  // namespace smokescan::python
