// The Python module `smokescan` (its compiled part, smokescan._smokescan): scenes, a 2D laser's
// scans and a 3D lidar's frames as numpy arrays, through the library's runs (pipeline/). Long
// calls release the GIL, report progress to a Python callable and stop on Ctrl-C; the library's
// errors are smokescan.Error carrying their one-line message.
#include <glog/logging.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <optional>
#include <thread>

#include "module_support.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/version.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/lidar/lidar_spec.hpp"
#include "smokescan/pipeline/bag_run.hpp"
#include "smokescan/pipeline/laser_run.hpp"
#include "smokescan/pipeline/lidar_run.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/sensor_config/sensor_kind.hpp"

namespace py = pybind11;
using namespace smokescan;
using namespace smokescan::python;

namespace {

/// One beam of one scan, a row of scan()'s array.
struct ScanRow {
    double time_s;
    double angle_rad;
    double range_m;  // NaN for an error value
    int64_t value;  // as the sensor reports it: a range in its unit, or an error code
    int32_t beam;
    bool error;
};

/// A 2D laser's run from Python's arguments (scan, record_bag).
ScanConfig laserConfig(const std::string& sensor, std::optional<double> t0, std::optional<double> t1,
                       const py::object& seed, const std::optional<std::string>& model)
{
    ScanConfig cfg;
    cfg.sensor = sensor;
    if (t0) cfg.from_s = finiteArg(*t0, "--from");
    if (t1) cfg.to_s = finiteArg(*t1, "--to");
    cfg.seed = seedArg(seed);
    cfg.keep_beams = false;
    if (model) cfg.model = modelArg(*model);
    return cfg;
}

/// A 3D lidar's run from Python's arguments (scan_lidar, record_bag).
LidarRunConfig lidarConfig(const std::string& sensor, const std::optional<std::string>& returns,
                           std::optional<double> t0, std::optional<double> t1, const py::object& seed)
{
    LidarRunConfig cfg;
    cfg.sensor = sensor;
    if (returns) {
        parseReturnMode(*returns, "--returns");
        cfg.returns = *returns;
    }
    if (t0) cfg.from_s = finiteArg(*t0, "--from");
    if (t1) cfg.to_s = finiteArg(*t1, "--to");
    cfg.seed = seedArg(seed);
    return cfg;
}

/// The names of a scene's surfaces, cameras or volumes.
template <class T>
std::vector<std::string> namesOf(const std::vector<T>& items)
{
    std::vector<std::string> v;
    for (const T& x : items) v.push_back(x.name);
    return v;
}

/// A pose as a 4×4 homogeneous matrix [m].
py::array_t<double> poseMatrix(const Pose& p)
{
    py::array_t<double> m({4, 4});
    auto a = m.mutable_unchecked<2>();
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) a(i, j) = i < 3 && j < 3 ? p.R(i, j) : i < 3 ? p.t(i) : j == 3 ? 1.0 : 0.0;
    return m;
}

py::array scanArray(const std::vector<Scan>& scans, const LrfSpec& spec)
{
    size_t n = 0;
    for (const Scan& s : scans) n += s.value.size();
    std::vector<ScanRow> rows(n);
    std::memset(static_cast<void*>(rows.data()), 0, n * sizeof(ScanRow));  // the padding too: equal runs, equal bytes
    size_t i = 0;
    for (const Scan& s : scans)
        for (size_t b = 0; b < s.value.size(); ++b, ++i) {
            const long long v = s.value[b];
            ScanRow& r = rows[i];
            r.time_s = s.time_s;
            r.angle_rad = s.angle_rad[b];
            r.range_m = spec.rangeOf(v);
            r.value = int64_t(v);
            r.beam = int32_t(b);
            r.error = spec.isErrorValue(v);
        }
    return ownedArray(std::move(rows));
}

/// One lidar frame for Python: its points without a copy, its poses and range image.
py::dict frameDict(LidarFrame&& f)
{
    py::dict d;
    d["index"] = f.index;
    d["start_s"] = f.start_s;
    d["end_s"] = f.end_s;
    d["start_pose"] = poseMatrix(f.start_pose);
    d["end_pose"] = poseMatrix(f.end_pose);
    if (!f.range_image.empty()) {
        py::array_t<float> img = ownedArray(std::move(f.range_image));
        d["range_image"] = img.reshape({py::ssize_t(f.channels), py::ssize_t(f.columns)});
    } else {
        d["range_image"] = py::none();
    }
    d["points"] = ownedArray(std::move(f.points));
    return d;
}

}  // namespace

PYBIND11_MODULE(_smokescan, m)
{
    m.doc() = "smokescan: laser range finders, 3D lidars and cameras simulated in smoke (the compiled part)";
    leaveSignalsToHost();  // Python's Ctrl-C is Python's: a KeyboardInterrupt, not the end of the process
    // Ceres logs through glog; the fits report what matters in their results (as the program does).
    if (!google::IsGoogleLoggingInitialized()) google::InitGoogleLogging("smokescan");
    FLAGS_minloglevel = google::GLOG_FATAL;
    FLAGS_stderrthreshold = google::GLOG_FATAL;
    FLAGS_logtostderr = false;
    PYBIND11_NUMPY_DTYPE(ScanRow, time_s, angle_rad, range_m, value, beam, error);
    PYBIND11_NUMPY_DTYPE(LidarPoint, x, y, z, range_m, intensity, ring, return_index, source, time_s, beam);
    static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
    error.attr("__module__") = "smokescan";
    error.attr("__doc__") =
        "A bad input or setting, with the library's one-line message (the file or option, then "
        "the problem)";
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const Error& e) {  // Cancelled too
            error(e.what());
        }
    });
    m.attr("__version__") = version();
    bindRender(m);
    bindAnalysis(m);
    bindVolume(m);
    bindOmni(m);

    py::class_<Scene, std::shared_ptr<Scene>>(m, "Scene", "A scene: surfaces, sensors, cameras and smoke over time")
        .def_readonly("source", &Scene::source, "The file it came from, or builtin:NAME")
        .def_readonly("t_start_s", &Scene::t_start_s, "Start of the scene's time line [s]")
        .def_readonly("t_end_s", &Scene::t_end_s, "End of the scene's time line [s]")
        .def_property_readonly(
            "sensors",
            [](const Scene& s) {
                std::vector<std::pair<std::string, std::string>> v;
                for (const SensorMount& m : s.sensors) v.emplace_back(m.name, sensorTypeName(m.config.type));
                return v;
            },
            "The 2D lasers mounted in the scene: (name, type) pairs")
        .def_property_readonly(
            "surfaces", [](const Scene& s) { return namesOf(s.surfaces); }, "Surface names")
        .def_property_readonly(
            "cameras", [](const Scene& s) { return namesOf(s.cameras); }, "Camera names")
        .def_property_readonly(
            "volumes", [](const Scene& s) { return namesOf(s.volumes); }, "Smoke volume names")
        .def(
            "with_smoke_scale",
            [](const Scene& s, double k) {
                auto out = std::make_shared<Scene>(s);
                for (SmokeVolume& v : out->volumes) v.timeline = v.timeline.scaled(k);
                return out;
            },
            py::arg("k"), "A copy of the scene whose smoke is k times as dense at every time (k >= 0)")
        .def("__repr__", [](const Scene& s) {
            return "<smokescan.Scene " + s.source + ": " + std::to_string(s.surfaces.size()) + " surfaces, " +
                std::to_string(s.sensors.size()) + " sensors, " + std::to_string(s.volumes.size()) + " smoke volumes>";
        });

    m.def(
        "load_scene",
        [](const py::object& name_or_path) {
            return std::make_shared<Scene>(loadScene(pathArg(name_or_path, "scene", false)));
        },
        py::arg("name_or_path"), "Loads a built-in scene by name (builtin_scenes()) or a scene file (.toml)");
    m.def("builtin_scenes", &builtinSceneNames, "The built-in scenes' names");

    m.def(
        "scan",
        [](std::shared_ptr<Scene> scene, const std::string& sensor, std::optional<double> t0, std::optional<double> t1,
           double rate_hz, py::object seed, std::optional<std::string> model, const py::object& sensor_file,
           double penetration_power, py::object progress) {
            ScanConfig cfg = laserConfig(sensor, t0, t1, seed, model);
            cfg.rate_hz = rate_hz;
            cfg.sensor_file = pathArg(sensor_file, "--sensor-file");
            if (!(penetration_power >= 0) || !std::isfinite(penetration_power))
                throw Error("--penetration-power", "must be a finite number > 0 (0: the mount's)");
            cfg.penetration_power = penetration_power;
            PyControl pc(std::move(progress));
            std::unique_ptr<LaserRun> run;
            const std::vector<Scan> scans = released(pc, [&](const RunControl& c) {
                run = std::make_unique<LaserRun>(*scene, cfg);
                return run->collect(c);
            });
            return scanArray(scans, run->spec());
        },
        py::arg("scene").none(false), py::arg("sensor") = "", py::arg("t0") = py::none(), py::arg("t1") = py::none(),
        py::arg("rate_hz") = 1.0, py::arg("seed") = 1, py::arg("model") = py::none(),
        py::arg("sensor_file") = py::none(), py::arg("penetration_power") = 0.0, py::arg("progress") = py::none(),
        "A 2D laser's scans from t0 to t1 (default: the scene's span) at rate_hz: one row per beam and scan");

    m.def(
        "record_bag",
        [](std::shared_ptr<Scene> scene, const py::object& folder, const std::string& sensor, std::optional<double> t0,
           std::optional<double> t1, std::optional<double> rate_hz, py::object seed, std::optional<std::string> returns,
           std::optional<std::string> model, py::object progress) {
            const std::string path = pathArg(folder, "path", false);
            PyControl pc(std::move(progress));
            BagRunResult r;
            if (isLidarRun(*scene, sensor)) {
                if (model) throw Error("--model", "is for the 2D lasers; the " + sensor + " has its own receiver");
                LidarRunConfig cfg = lidarConfig(sensor, returns, t0, t1, seed);
                cfg.rate_hz = rate_hz.value_or(0.0);
                r = released(pc, [&](const RunControl& c) { return recordLidarBag(*scene, cfg, path, c); });
            } else {
                if (returns) throw Error("--returns", "is for a 3D lidar");
                ScanConfig cfg = laserConfig(sensor, t0, t1, seed, model);
                if (rate_hz) cfg.rate_hz = *rate_hz;
                r = released(pc, [&](const RunControl& c) { return recordLaserBag(*scene, cfg, path, c); });
            }
            py::dict d;
            d["messages"] = r.messages;
            d["readings"] = r.readings;
            return d;
        },
        py::arg("scene").none(false), py::arg("path"), py::arg("sensor") = "", py::arg("t0") = py::none(),
        py::arg("t1") = py::none(), py::arg("rate_hz") = py::none(), py::arg("seed") = 1,
        py::arg("returns") = py::none(), py::arg("model") = py::none(), py::arg("progress") = py::none(),
        "Records a scan run as a ROS 2 bag in the new folder `path`: a scene's 2D laser (as scan()) or a 3D lidar "
        "preset (as scan_lidar()); the folder appears whole or not at all");

    m.def(
        "scan_lidar",
        [](std::shared_ptr<Scene> scene, const std::string& sensor, std::optional<std::string> returns, double rate_hz,
           long long columns, std::optional<double> t0, std::optional<double> t1, py::object seed,
           py::object progress) {
            LidarRunConfig cfg = lidarConfig(sensor, returns, t0, t1, seed);
            cfg.rate_hz = rate_hz;
            if (columns < 0 || columns > 8192) throw Error("--columns", "must lie in 1…8192 (0: the preset's)");
            cfg.columns = int(columns);
            PyControl pc(std::move(progress));
            std::vector<LidarFrame> frames = released(pc, [&](const RunControl& c) {
                const LidarRun run(*scene, cfg);
                return run.collect(c);
            });
            py::list out;
            for (LidarFrame& f : frames) out.append(frameDict(std::move(f)));
            return out;
        },
        py::arg("scene").none(false), py::arg("sensor") = "vlp16", py::arg("returns") = py::none(),
        py::arg("rate_hz") = 0.0, py::arg("columns") = 0, py::arg("t0") = py::none(), py::arg("t1") = py::none(),
        py::arg("seed") = 1, py::arg("progress") = py::none(),
        "A 3D lidar's frames (a preset or preset file) on the scene's default lidar mount, one dict a frame");
}
