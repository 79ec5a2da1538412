// smokescan.omnirange: the omnidirectional camera as a colour-based rangefinder beside a laser
// (pipeline/omnirange_run.hpp), its readings as numpy arrays.
#include <pybind11/stl.h>

#include <memory>
#include <optional>

#include "module_support.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/omni/omni_compare.hpp"
#include "smokescan/pipeline/omnirange_run.hpp"

namespace smokescan::python {
namespace {

/// The frames' readings as arrays, one row a frame.
py::dict readingsDict(const std::vector<OmniFrame>& frames, const OmniComparison& cmp)
{
    const size_t F = frames.size(), S = F ? frames[0].omni.range_m.size() : 0, B = F ? frames[0].laser_value.size() : 0;
    std::vector<double> time(F), range(F * S), laser_range(F * B);
    std::vector<uint8_t> status(F * S);
    std::vector<int64_t> laser_value(F * B);
    for (size_t k = 0; k < F; ++k) {
        const OmniFrame& f = frames[k];
        time[k] = f.time_s;
        for (size_t s = 0; s < S; ++s) {
            range[k * S + s] = f.omni.range_m[s];
            status[k * S + s] = uint8_t(f.omni.status[s]);
        }
        for (size_t b = 0; b < B; ++b) {
            laser_range[k * B + b] = f.laser_range_m[b];
            laser_value[k * B + b] = f.laser_value[b];
        }
    }
    const auto rows = [F](py::array a, size_t cols) { return a.reshape({py::ssize_t(F), py::ssize_t(cols)}); };
    py::dict d;
    d["time_s"] = ownedArray(std::move(time));
    d["angle_rad"] = ownedArray(F ? std::vector<double>(frames[0].omni.angle_rad) : std::vector<double>{});
    d["range_m"] = rows(ownedArray(std::move(range)), S);
    d["status"] = rows(ownedArray(std::move(status)), S);
    d["laser_angle_rad"] = ownedArray(F ? std::vector<double>(frames[0].laser_angle_rad) : std::vector<double>{});
    d["laser_range_m"] = rows(ownedArray(std::move(laser_range)), B);
    d["laser_value"] = rows(ownedArray(std::move(laser_value)), B);
    py::dict c;
    c["pairs"] = cmp.pairs;
    c["outliers"] = cmp.outliers;
    c["mean_abs_m"] = cmp.meanAbsM();
    c["mean_percent"] = cmp.meanPercent();
    c["mean_signed_m"] = cmp.meanSignedM();
    d["comparison"] = c;
    return d;
}

}  // namespace

void bindOmni(py::module_& m)
{
    const OmniRunConfig defaults;
    m.def(
        "omnirange",
        [](std::shared_ptr<Scene> scene, std::optional<std::vector<double>> train, const py::object& histogram,
           std::optional<double> t0, std::optional<double> t1, double rate_hz, py::object seed, long long spp,
           const std::string& camera, const std::string& laser, double threshold, int n_behind, int k_free,
           int scanlines, double min_range_m, double max_range_m, double outlier_m, double floor_z_m, double exposure,
           py::object progress) {
            OmnirangeRunConfig cfg;
            if (train) cfg.train_s = *train;
            cfg.histogram = pathArg(histogram, "--histogram");
            if (t0) cfg.from_s = finiteArg(*t0, "--from");
            if (t1) cfg.to_s = finiteArg(*t1, "--to");
            cfg.rate_hz = rate_hz;
            cfg.run.seed = seedArg(seed);
            if (spp < 1 || spp > limits::kSpp) throw Error("--spp", "must lie in 1…" + std::to_string(limits::kSpp));
            cfg.run.spp = int(spp);
            cfg.run.camera = camera;
            cfg.run.laser = laser;
            cfg.run.range.threshold = threshold;
            cfg.run.range.filter.n_behind = n_behind;
            cfg.run.range.filter.k_free = k_free;
            cfg.run.range.scanlines = scanlines;
            cfg.run.range.min_range_m = min_range_m;
            cfg.run.range.max_range_m = max_range_m;
            cfg.run.outlier_m = outlier_m;
            cfg.run.floor_z_m = finiteArg(floor_z_m, "--floor-z");
            cfg.run.exposure = finiteArg(exposure, "--exposure");
            PyControl pc(std::move(progress));
            std::vector<OmniFrame> frames;
            OmniComparison cmp;
            cmp.outlier_m = cfg.run.outlier_m;
            double used_exposure = 0;
            long long trained = 0;
            released(pc, [&](const RunControl& c) {
                OmnirangeRun run(*scene, cfg);
                const long long T = (long long)cfg.train_s.size(), F = (long long)run.times().size();
                // Kept in memory: bounded before any frame is rendered.
                const double readings = double(F) * double(cfg.run.range.scanlines + run.omni().laser().spec().n_beams);
                if (readings > double(limits::kKeptReadings))
                    throw Error("--rate",
                                "would keep " + std::to_string((long long)readings) + " readings (at most " +
                                    std::to_string(limits::kKeptReadings) + ")");
                RunControl training = c, reading = c;
                if (c.progress) {
                    training.progress = [&](long long d, long long) { c.progress(d, T + F); };
                    reading.progress = [&](long long d, long long) { c.progress(T + d, T + F); };
                }
                run.train(training);
                run.run(
                    [&](OmniFrame&& f) {
                        cmp.add(f);
                        frames.push_back(std::move(f));
                    },
                    reading);
                used_exposure = run.omni().exposure();
                trained = run.trainedPixels();
                return 0;
            });
            py::dict d = readingsDict(frames, cmp);
            d["exposure"] = used_exposure;
            d["trained_pixels"] = trained;
            return d;
        },
        py::arg("scene").none(false), py::kw_only(), py::arg("train") = py::none(), py::arg("histogram") = py::none(),
        py::arg("t0") = py::none(), py::arg("t1") = py::none(), py::arg("rate_hz") = 1.0, py::arg("seed") = 1,
        py::arg("spp") = defaults.spp, py::arg("camera") = "", py::arg("laser") = "",
        py::arg("threshold") = defaults.range.threshold, py::arg("n_behind") = defaults.range.filter.n_behind,
        py::arg("k_free") = defaults.range.filter.k_free, py::arg("scanlines") = defaults.range.scanlines,
        py::arg("min_range_m") = defaults.range.min_range_m, py::arg("max_range_m") = defaults.range.max_range_m,
        py::arg("outlier_m") = defaults.outlier_m, py::arg("floor_z_m") = defaults.floor_z_m,
        py::arg("exposure") = defaults.exposure, py::arg("progress") = py::none(),
        "`smokescan omnirange`: the omni camera as a colour-based rangefinder beside the scene's laser (docs/"
        "omnicam.md), trained at the times `train` (or from a saved `histogram`), read from t0 to t1 at rate_hz. "
        "A dict: time_s (F), angle_rad (S scanlines), range_m (F×S, m; the floor distance), status (F×S uint8: 0 "
        "hit, 1 below the minimum range, 2 at the maximum), laser_angle_rad (B), laser_range_m (F×B, NaN for an "
        "error value), laser_value (F×B int64, as the laser reports), comparison (the omnicam against the laser: "
        "pairs, outliers, mean_abs_m, mean_percent, mean_signed_m), exposure, trained_pixels");
}

}  // namespace smokescan::python
