// `smokescan fit`: a recorded laser log and the camera's saturation → clock offset, thresholds,
// penetration power, range bias/noise; a sensor file `smokescan scan` uses as it is, a JSON report,
// the aligned streams and the paper's Fig. 5 and 9.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <set>

#include "commands.hpp"
#include "smokescan/bag/bag_input.hpp"
#include "smokescan/calib/calibration.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/fit/covariates.hpp"
#include "smokescan/fit/fit_inputs.hpp"
#include "smokescan/fit/fit_report.hpp"
#include "smokescan/fit/omni_fit.hpp"
#include "smokescan/fit/plume_fit.hpp"
#include "smokescan/io/run_files.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/sensor_config/laser_kind.hpp"
#include "smokescan/sensor_config/sensor_file.hpp"

namespace smokescan::cli {
namespace {
namespace fs = std::filesystem;

struct FitArgs {
    std::string laser, saturation, scene, sensor, surfaces_file, calibration = "bocas", patch, unit = "mm";
    std::string bag, topic, image_topic;
    std::vector<std::string> rects, polygons;
    std::string sensor_type = "urg04lx", prefix = "target_", out, report, plots, aligned, covariates, model = "paper";
    std::vector<std::string> surfaces;
    double offset = 0;
    bool fixed_offset = false, lenient = false, covariates_all = false;
    SensorFitConfig cfg;
    OmniFitConfig omni;
    std::set<std::string> omni_given;  ///< which of --max-range, --floor-z, --tolerance were given (the omnicam's)
};

/// OUT with its extension replaced: sensor.toml → sensor_report.json.
std::string beside(const std::string& out, const std::string& suffix)
{
    fs::path p(out);
    return (p.parent_path() / (p.stem().string() + suffix)).string();
}

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

/// The report, the aligned streams and the figures (all but the report only when the fit
/// succeeded), and the summary; throws when no threshold was fitted (the report stays).
void writeFitOutputs(const FitArgs& a, RunFiles& files, const SensorFitResult& r, const FitSources& sources,
                     const UrgNoiseFloorResult* phys)
{
    writeFitReportJson(files.stage(a.report), r, a.cfg, sources, phys);
    const bool failed = !r.ok() || (phys && !phys->ok);
    if (failed) files.commit();
    if (!failed && !a.aligned.empty()) writeAlignedCsv(files.stage(a.aligned), r);
    if (!failed && !r.aligned.empty()) {
        writeFitTimePlot(files.stage(a.plots + "_fig5.png"), r, std::max(0, r.reference));
        writeFitSaturationPlot(files.stage(a.plots + "_fig9.png"), r, a.cfg);
    }
    say("%s", fitSummaryText(r, sources.skipped.size()).c_str());
    if (!r.ok())
        throw Error(a.laser.empty() ? a.bag : a.laser,
                    "no threshold could be fitted: " +
                        (r.diagnoses.empty() ? std::string("see ") + a.report : r.diagnoses.front()));
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
int runFitOmni(const FitArgs& a, const FitInputsConfig& ic, RunFiles& files)
{
    OmniFitConfig omni = a.omni;
    omni.camera = a.sensor;  // --sensor names the omni camera
    OmniFitInputs o = loadOmniFitInputs(ic, omni);
    if (o.in.scene) recordSceneInputs(files, a.scene, *o.in.scene);
    checkReference(a.cfg.reference, o.in.groups);
    SensorFitConfig cfg = a.cfg;
    for (const auto& v : o.in.scene->volumes)
        if (v.role == SmokeRole::Regional) {
            cfg.sigma_t_per_density = v.medium.sigmaT(550.0);  // the camera sees visible light: green's
            break;
        }
    say("omnicam '%s', viewpoint %.3f m above the floor: %lld of %lld readings more than %.2f m off the "
        "truth (%lld short, %lld long)\n",
        o.camera.c_str(), o.height_m, o.shorter + o.longer, o.readings, a.omni.tolerance_m, o.shorter, o.longer);
    SensorFitResult r = fitSensor(o.in.log, o.in.saturation, o.in.groups, o.spec, &o.in.calibration, cfg, o.failed);
    requireOnsets(r, cfg.reference);
    FitArgs shown = a;
    shown.cfg = cfg;
    writeFitOutputs(shown, files, r, o.in.sources, nullptr);
    const ThresholdFit& ref = r.thresholds[size_t(r.reference)];
    OmniSensorFile fitted;
    fitted.camera = o.camera;
    fitted.penetration_power = ref.penetration_power.value;
    fitted.extensions.clock_offset_s = r.offset.offset_s.value;
    fitted.tolerance_m = omni.tolerance_m;
    fitted.max_range_m = omni.max_range_m;
    fitted.floor_z_m = omni.floor_z_m;
    writeOmniSensorFile(
        files.stage(a.out), fitted,
        fmt("fitted by smokescan fit from %s and %s: S* = %.4f +/- %.4f on '%s' (half its readings "
            "more than %.2f m off the truth),\nP = %.5f +/- %.5f density.m along the camera's line "
            "of sight (report: %s)",
            a.laser.c_str(), a.saturation.c_str(), ref.S_star.value, ref.S_star.se, ref.group.c_str(),
            a.omni.tolerance_m, ref.penetration_power.value, ref.penetration_power.se, a.report.c_str()));
    files.commit();
    say("wrote %s (the omnicam's onset, from '%s'), %s, %s_fig5.png, %s_fig9.png%s%s\n", a.out.c_str(),
        ref.group.c_str(), a.report.c_str(), a.plots.c_str(), a.plots.c_str(), a.aligned.empty() ? "" : ", ",
        a.aligned.c_str());
    return 0;
}

int runFit(const FitArgs& a0)
{
    FitArgs a = a0;
    if (a.report.empty()) a.report = beside(a.out, "_report.json");
    if (a.plots.empty()) a.plots = beside(a.out, "");
    const std::string scans = scansSource(a.laser, a.bag, a.topic);
    RunFiles files;
    files.input(a.laser, "--laser");
    bagInputs(files, a.bag, "--bag");
    saturationInputs(files, a.saturation);
    files.input(a.surfaces_file, "--surfaces");
    files.input(a.calibration, "--calibration");
    files.output(a.out, "--out");
    files.output(a.report, "--report");
    files.output(a.plots + "_fig5.png", "--plots");
    files.output(a.plots + "_fig9.png", "--plots");
    files.output(a.aligned, "--aligned");
    files.output(a.covariates, "--covariates");
    if (!a.covariates.empty() && a.scene.empty())
        throw Error("--covariates", "needs --scene (the simulation's side of the table)");
    const SensorModel model = sensorModelOption("--model", a.model);
    if (model == SensorModel::Physical && a.scene.empty())
        throw Error("--model physical", "needs --scene (the geometry the noise floor is solved in)");
    const int sources = !a.scene.empty() + (!a.surfaces.empty() || !a.surfaces_file.empty());
    if (sources == 0) throw Error("fit", "say which beams see which surface: --scene, --surface or --surfaces");
    FitInputsConfig ic{a.laser,
                       a.saturation,
                       a.calibration,
                       a.patch,
                       a.scene,
                       a.sensor,
                       a.sensor_type,
                       a.prefix,
                       a.surfaces_file,
                       a.surfaces,
                       {parseRangeUnit(a.unit), a.lenient},
                       a.bag,
                       a.topic,
                       a.image_topic,
                       a.rects,
                       a.polygons};
    a.cfg.offset_s = a.offset;
    a.cfg.estimate_offset = !a.fixed_offset;
    if (recordedSensor(a.sensor_type).omnicam()) {
        if (!a.bag.empty()) throw Error("--bag", "holds a laser's scans; the omnicam's log is omnirange's (--laser)");
        if (model == SensorModel::Physical)
            throw Error("--model physical", "fits a laser's receiver; the omnicam is fitted with the paper model");
        if (!a.covariates.empty() || a.covariates_all)
            throw Error(a.covariates_all ? "--covariates-all" : "--covariates",
                        "are a laser's beams; the omnicam has none");
        return runFitOmni(a, ic, files);
    }
    if (!a.omni_given.empty())
        throw Error("fit", "--max-range, --floor-z and --tolerance are the omnicam's (--sensor-type omnicam)");
    FitInputs in = loadFitInputs(ic);
    if (in.scene) recordSceneInputs(files, a.scene, *in.scene);
    if (std::isfinite(in.sigma_t_per_density)) a.cfg.sigma_t_per_density = in.sigma_t_per_density;
    const LrfSpec spec = specFor(in.mount.config);
    checkReference(a.cfg.reference, in.groups);
    if (model == SensorModel::Physical && !laserKind(spec.type).fitsPhysicalModel())
        throw Error("--model physical",
                    std::string("fits the URG-04LX noise floor only; for a ") + sensorTypeName(spec.type) +
                        " in plumes see fit-plume");
    const SensorFitResult r = fitSensor(in.log, in.saturation, in.groups, spec, &in.calibration, a.cfg);
    std::unique_ptr<UrgNoiseFloorResult> phys;
    if (model == SensorModel::Physical && r.ok())
        phys = std::make_unique<UrgNoiseFloorResult>(
            fitUrgNoiseFloor(*in.scene, *in.surfaces, in.mount, r, size_t(r.reference), in.calibration));
    // A failed fit writes its report alone (it holds the diagnosis); a fitted one writes everything.
    if (r.ok() && !(phys && !phys->ok) && !a.covariates.empty())
        writeCovariates(files.stage(a.covariates), in.log, r, *in.scene, *in.surfaces, in.mount, spec,
                        a.covariates_all);
    writeFitOutputs(a, files, r, in.sources, phys.get());
    const ThresholdFit& ref = r.thresholds[size_t(r.reference)];
    SensorConfig fitted = in.mount.config;
    fitted.model = model;
    fitted.paper.penetration_power = ref.penetration_power.value;
    std::string comment =
        fmt("fitted by smokescan fit from %s and %s: S* = %.4f +/- %.4f on '%s', P = %.5f +/- %.5f density.m",
            scans.c_str(), a.saturation.c_str(), ref.S_star.value, ref.S_star.se, ref.group.c_str(),
            ref.penetration_power.value, ref.penetration_power.se);
    if (phys) {
        if (!phys->ok)
            throw Error(scans, "no physical noise floor: " + phys->diagnosis + " (report: " + a.report + ")");
        fitted.physical.noise_floor = phys->noise_floor.value;
        say("physical model on '%s': noise floor %.4g +/- %.2g (its onset at %.5f +/- %.5f density.m)\n",
            phys->group.c_str(), phys->noise_floor.value, phys->noise_floor.se, phys->onset_column.value,
            phys->onset_column.se);
        comment += fmt("; physical noise_floor = %.4g +/- %.2g", phys->noise_floor.value, phys->noise_floor.se);
    }
    writeSensorFile(files.stage(a.out), fitted, comment + " (report: " + a.report + ")");
    files.commit();
    say("wrote %s (%s model, from '%s'), %s, %s_fig5.png, %s_fig9.png%s%s%s%s\n", a.out.c_str(), a.model.c_str(),
        ref.group.c_str(), a.report.c_str(), a.plots.c_str(), a.plots.c_str(), a.aligned.empty() ? "" : ", ",
        a.aligned.c_str(), a.covariates.empty() ? "" : ", ", a.covariates.c_str());
    return 0;
}

struct PlumeArgs {
    std::string laser, bag, topic, scene, sensor, unit = "mm", out;
    bool lenient = false;
    PlumeFitConfig cfg;
};

int runFitPlume(const PlumeArgs& a)
{
    const std::string scans = scansSource(a.laser, a.bag, a.topic);
    const Scene scene = loadScene(a.scene);
    RunFiles files;
    files.input(a.laser, "--laser");
    bagInputs(files, a.bag, "--bag");
    recordSceneInputs(files, a.scene, scene);
    files.output(a.out, "--out");
    ReadOptions ro;
    ro.unit_m = parseRangeUnit(a.unit);
    ro.lenient = a.lenient;
    const int si = scene.findSensor(a.sensor.empty() ? "lms200" : a.sensor);
    if (si < 0) throw Error(scene.source, "no sensor '" + (a.sensor.empty() ? std::string("lms200") : a.sensor) + "'");
    const SensorMount& mount = scene.sensors[size_t(si)];
    // A bag's scans in the unit of the scene's sensor, which recorded them; named with their topic.
    std::string source = a.laser;
    RecordedLog log;
    if (a.bag.empty()) {
        log = readRecordedLog(a.laser, ro);
    } else {
        const BagLaserScans bag = readBagLaserScans(a.bag, a.topic);
        log = recordedLogOf(bag, specFor(mount.config));
        source = a.bag + " " + bag.topic;
    }
    const SurfaceSet surfaces(scene);
    const size_t beams = log.scans.front().range.size(), expected = size_t(specFor(mount.config).n_beams);
    if (laserKind(mount.config.type).fitsPlume() && beams != expected)  // else fitSickPlume names the kind
        throw Error(scans,
                    "has " + std::to_string(beams) + " beams a scan; the scene's sensor '" + mount.name + "' (" +
                        sensorTypeName(mount.config.type) + ") has " + std::to_string(expected) +
                        " (a log of another sensor?)");
    const PlumeFitResult r = fitSickPlume(log, scene, surfaces, mount, a.cfg);
    writePlumeFitJson(files.stage(a.out), r, a.cfg, source, a.scene);
    say("%zu beams crossed a plume (%zu bad lines skipped)\n", r.obs.size(), log.skipped.size());
    say("%-22s %6s %6s %6s %6s %12s\n", "peak density", "beams", "echo", "wall", "error", "depth [m]");
    for (const auto& b : r.bins)
        if (b.n)
            say("%9.3g - %9.3g  %6d %6d %6d %6d %12.3f\n", b.rho_lo, b.rho_hi, b.n, b.echo, b.surface, b.error,
                b.mean_depth_m);
    for (const auto& d : r.diagnoses) say("diagnosis: %s\n", d.c_str());
    if (!r.ok)
        throw Error(scans,
                    "no plume penetration could be fitted: " +
                        (r.diagnoses.empty() ? std::string("see ") + a.out : r.diagnoses.front()));
    say("penetration depth D = %.3f +/- %.3f m at density %.5f, falling as density^-k, k = %.2f +/- %.2f\n",
        r.depth_m.value, r.depth_m.se, r.rho_ref, r.exponent.value, r.exponent.se);
    if (std::isfinite(r.rho_50.value))
        say("half the beams echo from the plume at peak density %.5f +/- %.5f (slope %.2f +/- %.2f)\n", r.rho_50.value,
            r.rho_50.se, r.slope.value, r.slope.se);
    files.commit();
    say("wrote %s\n", a.out.c_str());
    return 0;
}

}  // namespace

void addFitPlume(CLI::App& app, Runner& run)
{
    auto a = std::make_shared<PlumeArgs>();
    auto* c = app.add_subcommand(
        "fit-plume",
        "Fit a Sick LMS200's penetration into smoke plumes: reported distance against the scene's plume density");
    addScansOptions(c, a->laser, a->bag, a->topic, "Sick laser log (the paper's format)");
    c->add_option("--scene", a->scene, "Scene with the plumes and the Sick (built-in name or file)")->required();
    c->add_option("--out", a->out, "JSON report to write")->required();
    c->add_option("--sensor", a->sensor, "Sensor in the scene (default: the first lms200)");
    c->add_option("--unit", a->unit, "Range unit of the log: mm, cm, m")->capture_default_str();
    c->add_flag("--lenient", a->lenient, "Skip bad lines instead of failing");
    c->add_option("--time-offset", a->cfg.time_offset_s, "Scene time - log time [s]")
        ->capture_default_str()
        ->check(finite());
    c->add_option("--bins", a->cfg.bins, "Density bins")->capture_default_str()->check(intRange(1, limits::kPlumeBins));
    c->callback([a, &run] { run = [a] { return runFitPlume(*a); }; });
}

void addFit(CLI::App& app, Runner& run)
{
    auto a = std::make_shared<FitArgs>();
    auto* c = app.add_subcommand(
        "fit", "Fit a laser's smoke thresholds from a recorded log and the camera's saturation; write a sensor file");
    addScansOptions(c, a->laser, a->bag, a->topic, "Laser log (the paper's format, as `scan` writes it)");
    addSaturationOptions(c, a->saturation, a->image_topic, a->rects, a->polygons,
                         "Saturation CSV: time_s,saturation[,patches] (as `saturation` writes it)")
        ->required();
    c->add_option("--out", a->out, "Sensor file to write (TOML, for `scan --sensor-file`)")->required();
    c->add_option("--scene", a->scene, "Scene whose surfaces name the beam groups (built-in name or file)");
    c->add_option("--sensor", a->sensor, "Sensor in the scene (default: the first of --sensor-type)");
    c->add_option("--target-prefix", a->prefix, "With --scene: surfaces whose names start with it form the groups")
        ->capture_default_str();
    c->add_option("--surface", a->surfaces, "A beam group: NAME=A0:A1[,A2:A3][@RANGE_M], degrees (repeatable)");
    c->add_option("--surfaces", a->surfaces_file, "Beam groups file: lines NAME A0_DEG A1_DEG [RANGE_M]");
    c->add_option("--sensor-type", a->sensor_type,
                  "urg04lx or lms200 (without --scene), or omnicam: the omnirange log, its failures against the "
                  "--scene's truth (--sensor then names the omni camera)")
        ->capture_default_str();
    addOmniClassOptions(c, a->omni, a->omni_given);
    c->add_option("--unit", a->unit, "Range unit of the log: mm, cm, m")->capture_default_str();
    c->add_flag("--lenient", a->lenient, "Skip bad lines (counted and listed in the report) instead of failing");
    c->add_option("--calibration", a->calibration, "Density-saturation calibration JSON, or a built-in name")
        ->capture_default_str();
    c->add_option("--patch", a->patch, "Use this patch's saturation column and calibration curve");
    c->add_option("--offset", a->offset,
                  "Clock offset camera - laser [s], within +/-1e5: the search centre, or the value with "
                  "--fixed-offset")
        ->capture_default_str()
        ->check(range(-1e5, 1e5));
    c->add_flag("--fixed-offset", a->fixed_offset, "Do not estimate the offset");
    c->add_option("--offset-window", a->cfg.offset_window_s, "Offset search half-width [s]")
        ->capture_default_str()
        ->check(nonnegative());
    addChoice(c, "--link", a->cfg.link, {{"probit", ErrorLink::Probit}, {"logistic", ErrorLink::Logistic}},
              "Threshold link, default probit");
    c->add_option("--smooth", a->cfg.smooth_s, "Saturation smoothing window [s]")
        ->capture_default_str()
        ->check(nonnegative());
    c->add_option(
         "--bootstrap", a->cfg.bootstrap,
         "Replicates of the parametric bootstrap behind the errors on S* and the offset: 0 (the analytic floor) or "
         "10-1000")
        ->capture_default_str()
        ->check(intRange(0, 1000));
    c->add_option("--model", a->model,
                  "Sensor file model: paper (penetration power) or physical (URG noise floor solved in --scene)")
        ->capture_default_str();
    c->add_option("--reference", a->cfg.reference,
                  "Group whose penetration power goes into the sensor file (default: most beams)");
    c->add_option("--report", a->report, "JSON report (default: OUT's name + _report.json)");
    c->add_option("--plots", a->plots, "Plot path prefix: PREFIX_fig5.png, PREFIX_fig9.png (default: OUT's name)");
    c->add_option("--aligned", a->aligned, "Also write the aligned streams (CSV)");
    c->add_option("--covariates", a->covariates,
                  "Also write per-beam, per-scan covariates from the scene (CSV; needs --scene)");
    c->add_flag("--covariates-all", a->covariates_all, "Covariates for every beam, not only the groups'");
    c->callback([a, &run] { run = [a] { return runFit(*a); }; });
}

}  // namespace smokescan::cli
