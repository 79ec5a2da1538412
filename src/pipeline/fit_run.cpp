#include "smokescan/pipeline/fit_run.hpp"

#include <algorithm>
#include <cmath>

#include "smokescan/bag/bag_input.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/fit/fit_report.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/sensor_config/laser_kind.hpp"
#include "watched.hpp"

namespace smokescan {
namespace {

/// --reference must name one of the groups.
void checkReference(const std::string& reference, const std::vector<BeamGroup>& groups)
{
    if (reference.empty()) return;
    std::string names;
    bool known = false;
    for (const auto& g : groups) {
        names += (names.empty() ? "" : ", ") + g.name;
        known |= g.name == reference;
    }
    if (!known) throw Error("--reference", "no group '" + reference + "' (groups: " + names + ")");
}

/// An omnicam's onset must be in the log: a wall counts only where its failures cross half its
/// readings (a few clear-air misreadings are not an onset) and S* and P are finite, S* within the
/// saturation the log saw. The others lose their fit (with the reason); the reference is the
/// named or largest one left.
void requireOnsets(SensorFitResult& r, const std::string& reference)
{
    double s_lo = kInf, s_hi = -kInf;
    for (const AlignedScan& a : r.aligned)
        if (std::isfinite(a.saturation)) s_lo = std::min(s_lo, a.saturation), s_hi = std::max(s_hi, a.saturation);
    r.reference = -1;
    for (size_t g = 0; g < r.thresholds.size(); ++g) {
        ThresholdFit& th = r.thresholds[g];
        if (!th.fitted) continue;
        bool above = false, below = false;
        for (const AlignedScan& a : r.aligned)
            if (a.beams[g] > 0 && std::isfinite(a.saturation)) {
                above |= 2 * a.errors[g] > a.beams[g];
                below |= 2 * a.errors[g] < a.beams[g];
            }
        std::string why;
        if (!above || !below)
            why = above ? "it failed on more than half its readings in every scan"
                        : "it never failed on more than half its readings in a scan";
        else if (!std::isfinite(th.S_star.value) || !std::isfinite(th.penetration_power.value) ||
                 !(th.penetration_power.value > 0) || th.S_star.value < s_lo || th.S_star.value > s_hi)
            why = fmt("S* = %.4g lies outside the saturation the log saw (%.4g to %.4g)", th.S_star.value, s_lo, s_hi);
        if (!why.empty()) {
            th.fitted = false;
            th.diagnosis += (th.diagnosis.empty() ? "" : "; ") + ("no onset: " + why);
            continue;
        }
        const bool named = th.group == reference;
        if (named || (reference.empty() && (r.reference < 0 || th.beams > r.thresholds[size_t(r.reference)].beams)))
            r.reference = int(g);
    }
    if (r.reference >= 0) return;
    for (const ThresholdFit& th : r.thresholds)
        if (!reference.empty() && th.group == reference) {
            r.diagnoses.insert(r.diagnoses.begin(),
                               "the reference group '" + reference + "' has no onset (" +
                                   (th.diagnosis.empty() ? "not fitted" : th.diagnosis) + ")");
            return;
        }
    r.diagnoses.insert(r.diagnoses.begin(),
                       "no wall's readings crossed from mostly right to mostly wrong as the smoke changed: no onset in "
                       "this log");
}

/// The omnicam's log: its failures against the scene's truth, fitted as a laser's errors are.
void fitOmni(const FitRunConfig& a, FitRunResult& out)
{
    OmniFitConfig omni = a.omni;
    omni.camera = a.in.sensor;  // --sensor names the omni camera
    OmniFitInputs o = loadOmniFitInputs(a.in, omni);
    if (a.on_scene && o.in.scene) a.on_scene(*o.in.scene);
    checkReference(a.fit.reference, o.in.groups);
    out.used = a.fit;
    for (const auto& v : o.in.scene->volumes)
        if (v.role == SmokeRole::Regional) {
            out.used.sigma_t_per_density = v.medium.sigmaT(550.0);  // the camera sees visible light: green's
            break;
        }
    out.omni_readings = OmniReadings{o.camera, o.height_m, o.readings, o.shorter, o.longer};
    out.fit = fitSensor(o.in.log, o.in.saturation, o.in.groups, o.spec, &o.in.calibration, out.used, o.failed);
    requireOnsets(out.fit, out.used.reference);
    out.spec = o.spec;
    out.inputs = std::move(o.in);
    if (!out.fit.ok()) return;
    const ThresholdFit& ref = out.fit.thresholds[size_t(out.fit.reference)];
    OmniSensorFile fitted;
    fitted.camera = o.camera;
    fitted.penetration_power = ref.penetration_power.value;
    fitted.extensions.clock_offset_s = out.fit.offset.offset_s.value;
    fitted.tolerance_m = omni.tolerance_m;
    fitted.max_range_m = omni.max_range_m;
    fitted.floor_z_m = omni.floor_z_m;
    out.omni = fitted;
    out.sensor_comment =
        fmt("fitted by smokescan fit from %s and %s: S* = %.4f +/- %.4f on '%s' (half its readings "
            "more than %.2f m off the truth),\nP = %.5f +/- %.5f density.m along the camera's line of sight",
            out.scans.c_str(), a.in.saturation.c_str(), ref.S_star.value, ref.S_star.se, ref.group.c_str(),
            omni.tolerance_m, ref.penetration_power.value, ref.penetration_power.se);
}

/// A laser's log: its thresholds, and with the physical model its noise floor in the scene.
void fitLaser(const FitRunConfig& a, FitRunResult& out)
{
    if (!a.omni_given.empty())
        throw Error("fit", "--max-range, --floor-z and --tolerance are the omnicam's (--sensor-type omnicam)");
    out.inputs = loadFitInputs(a.in);
    FitInputs& in = out.inputs;
    if (a.on_scene && in.scene) a.on_scene(*in.scene);
    out.used = a.fit;
    if (std::isfinite(in.sigma_t_per_density)) out.used.sigma_t_per_density = in.sigma_t_per_density;
    out.spec = specFor(in.mount.config);
    checkReference(out.used.reference, in.groups);
    if (a.model == SensorModel::Physical && !laserKind(out.spec.type).fitsPhysicalModel())
        throw Error("--model physical",
                    std::string("fits the URG-04LX noise floor only; for a ") + sensorTypeName(out.spec.type) +
                        " in plumes see fit-plume");
    out.fit = fitSensor(in.log, in.saturation, in.groups, out.spec, &in.calibration, out.used);
    if (!out.fit.ok()) return;
    if (a.model == SensorModel::Physical) {
        out.physical =
            fitUrgNoiseFloor(*in.scene, *in.surfaces, in.mount, out.fit, size_t(out.fit.reference), in.calibration);
        if (!out.physical->ok) {
            out.failure = "no physical noise floor: " + out.physical->diagnosis;
            return;
        }
    }
    const ThresholdFit& ref = out.fit.thresholds[size_t(out.fit.reference)];
    SensorConfig fitted = in.mount.config;
    fitted.model = a.model;
    fitted.paper.penetration_power = ref.penetration_power.value;
    out.sensor_comment =
        fmt("fitted by smokescan fit from %s and %s: S* = %.4f +/- %.4f on '%s', P = %.5f +/- %.5f density.m",
            out.scans.c_str(), a.in.saturation.c_str(), ref.S_star.value, ref.S_star.se, ref.group.c_str(),
            ref.penetration_power.value, ref.penetration_power.se);
    if (out.physical) {
        fitted.physical.noise_floor = out.physical->noise_floor.value;
        out.sensor_comment += fmt("; physical noise_floor = %.4g +/- %.2g", out.physical->noise_floor.value,
                                  out.physical->noise_floor.se);
    }
    out.laser = fitted;
}

/// The fit, on whichever thread runs it (runFit watches it from the caller's).
FitRunResult fitRun(const FitRunConfig& a)
{
    FitRunResult out;
    out.scans = scansSource(a.in.laser, a.in.bag, a.in.topic);
    if (a.model == SensorModel::Physical && a.in.scene.empty())
        throw Error("--model physical", "needs --scene (the geometry the noise floor is solved in)");
    if (a.in.saturation.empty())
        throw Error("--saturation", "give the camera's saturation: a CSV (`smokescan saturation`) or a bag's frames");
    const int sources = !a.in.scene.empty() + (!a.in.surfaces.empty() || !a.in.surfaces_file.empty());
    if (sources == 0) throw Error("fit", "say which beams see which surface: --scene, --surface or --surfaces");
    if (!(std::abs(a.fit.offset_s) <= 1e5)) throw Error("--offset", "must lie in [-1e5, 1e5] s");
    if (!(a.fit.offset_window_s >= 0) || !std::isfinite(a.fit.offset_window_s))
        throw Error("--offset-window", "must be a finite number >= 0 [s]");
    if (!(a.fit.smooth_s >= 0) || !std::isfinite(a.fit.smooth_s))
        throw Error("--smooth", "must be a finite number >= 0 [s]");
    if (a.fit.bootstrap < 0 || a.fit.bootstrap > 1000) throw Error("--bootstrap", "must lie in 0…1000");
    if (recordedSensor(a.in.sensor_type).omnicam()) {
        if (!a.in.bag.empty())
            throw Error("--bag", "holds a laser's scans; the omnicam's log is omnirange's (--laser)");
        if (a.model == SensorModel::Physical)
            throw Error("--model physical", "fits a laser's receiver; the omnicam is fitted with the paper model");
        fitOmni(a, out);
    } else {
        fitLaser(a, out);
    }
    if (!out.fit.ok())
        out.failure = "no threshold could be fitted: " +
            (out.fit.diagnoses.empty() ? std::string("see its report") : out.fit.diagnoses.front());
    return out;
}

}  // namespace

FitRunResult runFit(FitRunConfig a, const RunControl& control)
{
    checkCancel(control);
    if (!control.cancel && !control.progress) return fitRun(a);
    // On a thread of its own, stopped between offset steps and bootstrap replicates.
    RenderWatch watch;
    a.fit.stop = &watch.stop;
    FitRunResult r = detail::runWatched<FitRunResult>([&] { return fitRun(a); }, watch,
                                                      [] { return std::pair<long long, long long>(0, 1); }, control);
    reportProgress(control, 1, 1);
    return r;
}

std::string fitRunJson(const FitRunResult& r)
{
    return fitReportJson(r.fit, r.used, r.inputs.sources, r.physical ? &*r.physical : nullptr);
}

PlumeRunResult runPlumeFit(const PlumeRunConfig& a, const RunControl& control)
{
    PlumeRunResult out;
    const std::string scans = scansSource(a.laser, a.bag, a.topic);
    out.source = scans;
    if (a.fit.bins < 1 || a.fit.bins > limits::kPlumeBins)
        throw Error("--bins", "must lie in 1…" + std::to_string(limits::kPlumeBins));
    if (!std::isfinite(a.fit.time_offset_s)) throw Error("--time-offset", "must be a finite number [s]");
    out.scene = std::make_unique<Scene>(loadScene(a.scene));
    const Scene& scene = *out.scene;
    if (a.on_scene) a.on_scene(scene);
    const std::string name = a.sensor.empty() ? std::string("lms200") : a.sensor;
    const int si = scene.findSensor(name);
    if (si < 0) throw Error(scene.source, "no sensor '" + name + "'");
    const SensorMount& mount = scene.sensors[size_t(si)];
    checkCancel(control);
    // A bag's scans in the unit of the scene's sensor, which recorded them; named with their topic.
    RecordedLog log;
    if (a.bag.empty()) {
        log = readRecordedLog(a.laser, a.read);
    } else {
        const BagLaserScans bag = readBagLaserScans(a.bag, a.topic);
        log = recordedLogOf(bag, specFor(mount.config));
        out.source = a.bag + " " + bag.topic;
    }
    out.skipped = log.skipped.size();
    const SurfaceSet surfaces(scene);
    const size_t beams = log.scans.front().range.size(), expected = size_t(specFor(mount.config).n_beams);
    if (laserKind(mount.config.type).fitsPlume() && beams != expected)  // else fitSickPlume names the kind
        throw Error(scans,
                    "has " + std::to_string(beams) + " beams a scan; the scene's sensor '" + mount.name + "' (" +
                        sensorTypeName(mount.config.type) + ") has " + std::to_string(expected) +
                        " (a log of another sensor?)");
    checkCancel(control);
    out.fit = fitSickPlume(log, scene, surfaces, mount, a.fit);
    reportProgress(control, 1, 1);
    return out;
}

}  // namespace smokescan
