#include "smokescan/sensors/scanner.hpp"

#include <tbb/parallel_for.h>

#include <cmath>

#include "smokescan/core/error.hpp"
#include "smokescan/core/random.hpp"
#include "smokescan/sensor_config/sensor_file.hpp"

namespace smokescan {

Scanner::Scanner(const Scene& scene, const SurfaceSet& surfaces, const ScanConfig& cfg)
    : scene_(scene), surfaces_(surfaces), cfg_(cfg)
{
    if (scene.sensors.empty()) throw Error(scene.source, "the scene has no sensors");
    const int si = cfg.sensor.empty() ? 0 : scene.findSensor(cfg.sensor);
    if (si < 0) {
        std::string names;
        for (const auto& s : scene.sensors)
            names += (names.empty() ? "" : ", ") + s.name + " (" + sensorTypeName(s.config.type) + ")";
        throw Error(scene.source, "no sensor named or of type '" + cfg.sensor + "' (sensors: " + names + ")");
    }
    mount_ = scene.sensors[size_t(si)];
    if (!cfg.sensor_file.empty()) applySensorFile(cfg.sensor_file, mount_.config);
    if (cfg.model) mount_.config.model = *cfg.model;
    if (cfg.penetration_power > 0) mount_.config.paper.penetration_power = cfg.penetration_power;
    for (const auto& [name, ext] : mount_.config.extensions.surfaces)
        if (scene.findSurface(name) < 0)
            throw Error(mount_.config.sensor_file.empty() ? scene.source : mount_.config.sensor_file,
                        "[extensions] name surface '" + name + "', which the scene " + scene.source + " does not have");
    model_ = makeBeamModel(mount_.config);
    fan_ = planarFan(model_->spec());
    if (!std::isfinite(cfg_.from_s)) cfg_.from_s = scene.t_start_s;
    if (!std::isfinite(cfg_.to_s)) cfg_.to_s = scene.t_end_s;
    if (!(cfg_.rate_hz > 0) || !std::isfinite(cfg_.rate_hz)) throw Error("--rate", "must be finite and > 0");
    scene.checkSpan(cfg_.from_s, cfg_.to_s);
    if ((cfg_.to_s - cfg_.from_s) * cfg_.rate_hz > 1e6) throw Error("--rate", "more than a million scans requested");
}

std::vector<double> Scanner::times() const
{
    std::vector<double> t;
    const long long n = (long long)std::floor((cfg_.to_s - cfg_.from_s) * cfg_.rate_hz + 1e-9);
    for (long long k = 0; k <= n; ++k) t.push_back(cfg_.from_s + double(k) / cfg_.rate_hz);
    return t;
}

Ray Scanner::beamRay(int i) const { return scene_.sensorAt(mount_, cfg_.from_s).beamRay(fan_[size_t(i)].azimuth_rad); }

Scan Scanner::scanAt(double t_s, uint64_t index) const
{
    const SmokeField field = SmokeField::at(scene_.volumes, t_s);
    const BeamWorld world{scene_, surfaces_, field, regionalSmokeRising(scene_, t_s)};
    const SensorMount at = scene_.sensorAt(mount_, t_s);  // on its robot, when it rides on one
    Scan scan;
    scan.time_s = t_s;
    const int n = int(fan_.size());
    scan.angle_rad.resize(size_t(n));
    scan.value.resize(size_t(n));
    scan.beams.resize(cfg_.keep_beams ? size_t(n) : 0);
    tbb::parallel_for(0, n, [&](int i) {
        KeyedRng rng(cfg_.seed, index, uint64_t(i));
        const double angle = fan_[size_t(i)].azimuth_rad;  // every beam at the scan's time (planarFan)
        BeamResult r = model_->read(world, LaserBeam(at.beamRay(angle), angle), rng, cfg_.keep_beams);
        scan.angle_rad[size_t(i)] = angle;
        scan.value[size_t(i)] = r.value;
        if (cfg_.keep_beams) scan.beams[size_t(i)] = std::move(r);
    });
    return scan;
}

}  // namespace smokescan
