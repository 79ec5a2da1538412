// smokescan.diagnose (and the other analyses of recorded data): the library's runs
// (pipeline/), their results as Report objects with the JSON reports' fields.
#include <pybind11/stl.h>

#include <optional>
#include <string>

#include "module_support.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/io/atomic_folder.hpp"
#include "smokescan/io/text_input.hpp"
#include "smokescan/pipeline/calibrate_run.hpp"
#include "smokescan/pipeline/diagnose_run.hpp"

namespace smokescan::python {
namespace {

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
                             const std::string& unit, bool lenient)
{
    FitInputsConfig in;
    in.scene = pathArg(scene, "--scene");
    in.laser = pathArg(laser, "--laser");
    in.bag = pathArg(bag, "--bag");
    in.topic = topic;
    in.saturation = pathArg(saturation, "--saturation");
    in.calibration = pathArg(calibration, "--calibration");
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

}  // namespace

void bindAnalysis(py::module_& m)
{
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
           double alpha, int max_findings, py::object seed, const py::object& out, py::object progress) {
            DiagnoseRunConfig cfg;
            cfg.in = inputsConfig(scene, laser, bag, topic, saturation, calibration, patch, sensor, sensor_type, unit,
                                  lenient);
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
        py::arg("progress") = py::none(),
        "`smokescan diagnose`: a recorded run (laser= log or bag=) replayed in the scene (a file or built-in "
        "name), what the simulation gets wrong, the cause and the extended model's held-out gain. Returns a "
        "Report with diagnosis.json's fields (docs/diagnosis.md); out= also writes the command's folder "
        "(diagnosis.json, report.md, sensor.toml), whole or not at all. progress(done, total) counts each "
        "round's candidates");
}

}  // namespace smokescan::python
