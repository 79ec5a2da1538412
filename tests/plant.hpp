#pragma once
// Planting effects in simulated recorded runs, through each effect's own mechanism (not the
// diagnosis' fit forms): a run (BOCAS, or a drawn room: random_room.hpp) is simulated with the paper model, every beam's true column
// and surface kept, then the log is rewritten beam by beam — ranges scaled by the smoke column,
// errors drawn from a shifted threshold, a sector failing, short returns, noise growing, a
// hysteresis in the onset — and the camera's clock shifted.
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "sanitized.hpp"
#include "smokescan/calib/calibration.hpp"
#include "smokescan/calib/saturation_predict.hpp"
#include "smokescan/core/random.hpp"
#include "smokescan/diagnose/diagnosis.hpp"
#include "smokescan/fit/fit_inputs.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/sensor_config/sensor_file.hpp"
#include "smokescan/sensors/scanner.hpp"

namespace smokescan::test {

/// A room, its camera prediction and the calibration its camera's saturation goes through (the
/// built-in BOCAS curve: a drawn room's saturation series is simulated through the same curve).
struct World {
    Scene scene;
    SurfaceSet surfaces{scene};
    CurveFitResult calib = readCalibrationJson("bocas");
    SaturationPredictor predictor{scene, surfaces, calib.curve};
    std::string laser = "hokuyo";  ///< the URG's name in the scene
    explicit World(Scene s) : scene(std::move(s)) {}
    World(const World&) = delete;
};

/// The built-in BOCAS room (loaded once).
inline World& bocasWorld()
{
    static World w(loadScene("bocas"));
    return w;
}

/// A simulated run: the scans with every beam's truth, the camera's saturation series, its room.
struct TrueRun {
    std::vector<Scan> scans;
    LrfSpec spec;
    SaturationSeries sat;
    const World* world = nullptr;
};

/// @brief A run of the room's URG (its scene model unless `sensor_file` says otherwise) from 0 to
/// `to_s` at rate_hz, saturation at 5 Hz with noise sigma_S; the camera's clock runs
/// `camera_offset_s` ahead of the laser's.
inline TrueRun simulateRun(const World& w, uint64_t seed, double to_s, double rate_hz = 1, double sigma_S = 0.01,
                           double camera_offset_s = 0, const std::string& sensor_file = "")
{
    ScanConfig sc;
    sc.sensor = w.laser;
    sc.from_s = 0;
    sc.to_s = to_s;
    sc.rate_hz = rate_hz;
    sc.seed = seed;
    sc.sensor_file = sensor_file;
    const Scanner scanner(w.scene, w.surfaces, sc);
    TrueRun r;
    r.world = &w;
    r.spec = scanner.spec();
    const auto times = scanner.times();
    for (size_t k = 0; k < times.size(); ++k) r.scans.push_back(scanner.scanAt(times[k], k));
    SaturationSimConfig ss;
    ss.from_s = 0;
    ss.to_s = to_s;
    ss.rate_hz = 5;
    ss.sigma = sigma_S;
    ss.clock_offset_s = camera_offset_s;
    ss.seed = seed + 7777;
    r.sat = simulateSaturation(w.scene, w.predictor, ss);
    return r;
}

/// @brief The BOCAS run of the URG-04LX (paper model) from 0 to `to_s` (simulateRun).
inline TrueRun simulateBocas(uint64_t seed, double to_s = 360, double rate_hz = 1, double sigma_S = 0.01,
                             double camera_offset_s = 0, const std::string& sensor_file = "")
{
    return simulateRun(bocasWorld(), seed, to_s, rate_hz, sigma_S, camera_offset_s, sensor_file);
}

/// One beam of a scan as the planting rules see it: its truth and its reported value [mm or code].
struct BeamView {
    size_t k, i;
    const BeamResult& truth;
    double angle_rad;
    double time_s;
    double column;  ///< true regional column [density·m]
    double previous_column;  ///< the same beam's column one scan before
    std::string surface;  ///< "" when nothing was hit
    long long& value;
};

/// @brief Rewrites each beam's reported value by `rule`.
inline void plant(TrueRun& r, const std::function<void(BeamView&)>& rule)
{
    const World& w = *r.world;
    for (size_t k = 0; k < r.scans.size(); ++k)
        for (size_t i = 0; i < r.scans[k].value.size(); ++i) {
            const BeamResult& t = r.scans[k].beams[i];
            const double prev = k > 0 ? r.scans[k - 1].beams[i].smoke.column_regional : t.smoke.column_regional;
            BeamView v{k,
                       i,
                       t,
                       r.scans[k].angle_rad[i],
                       r.scans[k].time_s,
                       t.smoke.column_regional,
                       prev,
                       t.hit.surface >= 0 ? w.scene.surfaces[size_t(t.hit.surface)].name : std::string(),
                       r.scans[k].value[i]};
            rule(v);
        }
}

/// @brief A valid reading of the true surface with the datasheet noise (for a beam a planted rule
/// turns from error to range), in mm.
inline long long surfaceReading(const TrueRun& r, const BeamView& v, KeyedRng& rng)
{
    const double L = v.truth.hit.t_m;
    return std::llround((L + r.spec.rangeSigma(L) * rng.normal()) / r.spec.unit_m);
}

/// @brief The run as FitInputs for the diagnosis (its room, its URG, the built-in calibration).
inline FitInputs inputsOf(const TrueRun& r)
{
    const World& w = *r.world;
    FitInputs in;
    in.log.path = "planted.log";
    in.log.unit_m = 0.001;
    for (const Scan& s : r.scans) {
        LaserLogScan l;
        l.time_s = s.time_s;
        l.angle_rad = s.angle_rad;
        for (long long v : s.value) l.range.push_back(double(v));
        in.log.scans.push_back(std::move(l));
    }
    in.saturation = r.sat;
    in.saturation.path = "planted_sat.csv";
    in.calibration = w.calib;
    in.scene = std::make_unique<Scene>(w.scene);
    in.surfaces = std::make_unique<SurfaceSet>(*in.scene);
    in.mount = w.scene.sensors[size_t(w.scene.findSensor(w.laser))];
    return in;
}

/// @brief A diagnosis's findings, one line each with their parameters, gain and p (for messages).
inline std::string findingsText(const DiagnosisResult& d)
{
    std::string s = d.verdict;
    for (const auto& f : d.findings) {
        s += "\n  " + f.cause + " " + f.target;
        for (const auto& [n, e] : f.parameters)
            s += " " + n + "=" + std::to_string(e.value) + "±" + std::to_string(e.se);
        s += " gain " + std::to_string(f.loglik_gain) + " p " + std::to_string(f.p_value);
    }
    return s;
}

/// A run diagnosed: its replay and the result.
struct Diagnosed {
    Replay replay;
    DiagnosisResult result;
};

/// @brief The run diagnosed with the scene's URG, its model `model` (paper when unset), then
/// `sensor_file` applied when given.
inline Diagnosed diagnoseWith(const TrueRun& r, const std::string& sensor_file = "",
                              SensorModel model = SensorModel::Paper)
{
    const FitInputs in = inputsOf(r);
    SensorConfig c = in.mount.config;
    c.model = model;
    if (!sensor_file.empty()) applySensorFile(sensor_file, c);
    Diagnosed d{replayRun(in, c, ReplayConfig{}), {}};
    d.result = diagnose(d.replay);
    return d;
}

}  // namespace smokescan::test
