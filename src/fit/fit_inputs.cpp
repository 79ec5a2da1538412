#include "smokescan/fit/fit_inputs.hpp"

#include <cmath>

#include "smokescan/bag/bag_input.hpp"
#include "smokescan/calib/calibration.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/fit/bag_saturation.hpp"
#include "smokescan/scene/scene_io.hpp"

namespace smokescan {

RecordedSensor recordedSensor(const std::string& name)
{
    RecordedSensor s;
    if (name == "omnicam") return s;
    s.laser = findLaserKind(name);
    if (!s.laser)
        throw Error("--sensor-type",
                    "unknown sensor type '" + name + "' (" + sensorTypeNames() + "; omnicam for an omnirange log)");
    return s;
}

namespace {

/// The sensor: the scene's (by name, else the first of the type), or the type's defaults.
SensorMount chooseSensor(const FitInputsConfig& cfg, const Scene* scene)
{
    SensorMount mount;
    mount.name = cfg.sensor_type;
    const RecordedSensor s = recordedSensor(cfg.sensor_type);
    if (s.omnicam()) throw Error("--sensor-type", "omnicam: an omnirange log is not a laser's (fit/omni_fit.hpp)");
    mount.config = SensorConfig::defaults(s.laser->type());
    if (!scene) return mount;
    const int si = cfg.sensor.empty() ? scene->findSensor(cfg.sensor_type) : scene->findSensor(cfg.sensor);
    if (si < 0) throw Error(scene->source, "no sensor '" + (cfg.sensor.empty() ? cfg.sensor_type : cfg.sensor) + "'");
    return scene->sensors[size_t(si)];
}

/// The beam groups: the scene's target surfaces, then a groups file, then --surface ranges.
void chooseGroups(const FitInputsConfig& cfg, FitInputs& in)
{
    if (in.scene) {
        in.groups = beamGroupsFromScene(*in.scene, *in.surfaces, in.mount, specFor(in.mount.config), cfg.prefix);
        if (in.groups.empty())
            throw Error(in.scene->source,
                        "no beam of sensor '" + in.mount.name + "' hits a surface named '" + cfg.prefix + "*'");
        in.sources.groups_from = in.scene->source;
    }
    if (!cfg.surfaces_file.empty()) {
        in.groups = readBeamGroupFile(cfg.surfaces_file);
        in.sources.groups_from = cfg.surfaces_file;
    }
    if (!cfg.surfaces.empty()) {
        if (cfg.surfaces_file.empty()) in.groups.clear();  // --surface replaces the scene's groups
        for (const auto& s : cfg.surfaces) in.groups.push_back(parseBeamGroup(s));
        in.sources.groups_from = cfg.surfaces_file.empty() ? "--surface" : cfg.surfaces_file + " and --surface";
    }
}

}  // namespace

/// The camera's saturation: a CSV, or measured on a bag's frames over the given patches.
SaturationSeries readSaturation(const FitInputsConfig& cfg)
{
    if (!isBagPath(cfg.saturation)) {
        if (!cfg.image_topic.empty() || !cfg.rects.empty() || !cfg.polygons.empty())
            throw Error(!cfg.image_topic.empty() ? "--image-topic" : "--rect/--polygon",
                        "measures a bag's frames, and --saturation " + cfg.saturation + " is not a bag");
        return readSaturationCsv(cfg.saturation, cfg.read);
    }
    return measureBagSaturation(cfg.saturation, cfg.image_topic, frameRegions(cfg.rects, cfg.polygons));
}

std::string scansSource(const std::string& laser, const std::string& bag, const std::string& topic)
{
    if (laser.empty() && bag.empty()) throw Error("--laser", "give the recorded scans: --laser LOG or --bag PATH");
    if (!laser.empty() && !bag.empty()) throw Error("--bag", "is in place of --laser; give one of them");
    if (!topic.empty() && bag.empty()) throw Error("--topic", "names a bag's topic; give --bag");
    return laser.empty() ? bag : laser;
}

SaturationSeries patchSeries(const SaturationSeries& s0, const std::string& patch)
{
    size_t p = 0;
    while (p < s0.patch_names.size() && s0.patch_names[p] != patch) ++p;
    if (p == s0.patch_names.size()) throw Error(s0.path, "has no patch column '" + patch + "'");
    SaturationSeries s = s0;
    s.time_s.clear();
    s.saturation.clear();
    for (size_t k = 0; k < s0.time_s.size(); ++k)
        if (std::isfinite(s0.patch[p][k])) {
            s.time_s.push_back(s0.time_s[k]);
            s.saturation.push_back(s0.patch[p][k]);
        }
    if (s.time_s.empty()) throw Error(s0.path, "patch '" + patch + "' has no values");
    return s;
}

FitInputs loadFitData(const FitInputsConfig& cfg)
{
    FitInputs in;
    if (!cfg.scene.empty()) {
        in.scene = std::make_unique<Scene>(loadScene(cfg.scene));
        in.surfaces = std::make_unique<SurfaceSet>(*in.scene);
    }
    std::string laser = cfg.laser;
    if (cfg.bag.empty()) {
        in.log = readRecordedLog(cfg.laser, cfg.read);
    } else {  // the scans in the unit of the sensor that recorded them
        const BagLaserScans bag = readBagLaserScans(cfg.bag, cfg.topic);
        in.log = recordedLogOf(bag, specFor(chooseSensor(cfg, in.scene.get()).config));
        laser = cfg.bag + " " + bag.topic;
    }
    if (cfg.saturation.empty() && (!cfg.image_topic.empty() || !cfg.rects.empty() || !cfg.polygons.empty()))
        throw Error(!cfg.image_topic.empty() ? "--image-topic" : "--rect/--polygon",
                    "measures a bag's camera frames: give the bag as --saturation");
    // No saturation (diagnose without a camera): the scene's own smoke time line is replayed.
    const SaturationSeries sat0 = cfg.saturation.empty() ? SaturationSeries{} : readSaturation(cfg);
    if (!cfg.saturation.empty()) in.saturation = cfg.patch.empty() ? sat0 : patchSeries(sat0, cfg.patch);
    in.calibration = readCalibrationJson(cfg.calibration, cfg.patch);
    // A bag's saturation is named with its Image topic, as the scans with theirs.
    in.sources = {laser, cfg.saturation.empty() ? "" : sat0.path, cfg.calibration, "", in.log.unit_m, {}};
    in.sources.skipped = in.log.skipped;
    in.sources.skipped.insert(in.sources.skipped.end(), sat0.skipped.begin(), sat0.skipped.end());
    return in;
}

FitInputs loadFitInputs(const FitInputsConfig& cfg)
{
    FitInputs in = loadFitData(cfg);
    in.mount = chooseSensor(cfg, in.scene.get());
    const LrfSpec spec = specFor(in.mount.config);
    const size_t beams = in.log.scans.front().range.size();
    if (beams != size_t(spec.n_beams))
        throw Error(in.log.path,
                    "has " + std::to_string(beams) + " beams a scan; the sensor '" + in.mount.name + "' (" +
                        sensorTypeName(spec.type) + ") has " + std::to_string(spec.n_beams) +
                        " (a log of another sensor? give --sensor or --sensor-type)");
    chooseGroups(cfg, in);
    if (in.scene)
        for (const auto& v : in.scene->volumes)
            if (v.role == SmokeRole::Regional) {
                in.sigma_t_per_density = v.medium.sigmaT(specFor(in.mount.config).wavelength_nm);
                break;
            }
    return in;
}

}  // namespace smokescan
