// `smokescan fit`: a recorded laser log and the camera's saturation → clock offset, thresholds,
// penetration power, range bias/noise; a sensor file `smokescan scan` uses as it is, a JSON report,
// the aligned streams and the paper's Fig. 5 and 9.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>

#include "commands.hpp"
#include "progress.hpp"
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
#include "smokescan/pipeline/fit_run.hpp"
#include "smokescan/pipeline/lidar_fit_run.hpp"
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
    LidarRunConfig lidar;  ///< --points: a 3D lidar's frames (its sensor, returns, columns, rate)
    std::string points;
};

/// OUT with its extension replaced: sensor.toml → sensor_report.json.
std::string beside(const std::string& out, const std::string& suffix)
{
    fs::path p(out);
    return (p.parent_path() / (p.stem().string() + suffix)).string();
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

/// The omnicam's onset file, its report and figures.
int finishFitOmni(const FitArgs& a, RunFiles& files, FitRunResult& r)
{
    const OmniReadings& o = *r.omni_readings;
    say("omnicam '%s', viewpoint %.3f m above the floor: %lld of %lld readings more than %.2f m off the "
        "truth (%lld short, %lld long)\n",
        o.camera.c_str(), o.height_m, o.shorter + o.longer, o.readings, a.omni.tolerance_m, o.shorter, o.longer);
    FitArgs shown = a;
    shown.cfg = r.used;
    writeFitOutputs(shown, files, r.fit, r.inputs.sources, nullptr);  // throws when nothing was fitted
    const ThresholdFit& ref = r.fit.thresholds[size_t(r.fit.reference)];
    writeOmniSensorFile(files.stage(a.out), *r.omni, r.sensor_comment + " (report: " + a.report + ")");
    files.commit();
    say("wrote %s (the omnicam's onset, from '%s'), %s, %s_fig5.png, %s_fig9.png%s%s\n", a.out.c_str(),
        ref.group.c_str(), a.report.c_str(), a.plots.c_str(), a.plots.c_str(), a.aligned.empty() ? "" : ", ",
        a.aligned.c_str());
    return 0;
}

/// The options a 3D lidar's fit takes; --points, --returns, --columns and --rate are its alone.
const std::set<std::string> kLidarFitOptions = {"--points",  "--scene",   "--out",  "--sensor", "--report",
                                                "--returns", "--columns", "--rate", "--topic"};

/// A 3D lidar's frames (--points): each surface's reflectance factor from the recorded
/// intensities, the preset extended by them (--out) and the report (--report).
int fitLidarFrames(const FitArgs& a0)
{
    FitArgs a = a0;
    if (a.points.empty()) throw Error("--points", "names no folder");
    if (!isLidarPresetFile(a.out) || fs::path(a.out).stem().empty())
        throw Error("--out",
                    "'" + a.out + "' must name a .toml file: scan and diagnose take a preset file by its suffix");
    if (a.report.empty()) a.report = beside(a.out, "_report.json");
    if (a.scene.empty()) throw Error("--scene", "names the scene the frames of --points were recorded in");
    if (a.sensor.empty())
        throw Error("--sensor", "names the lidar whose frames --points holds (a preset or a preset file)");
    LidarFitRunConfig cfg;
    cfg.frames.scene = a.scene;
    cfg.frames.points = a.points;
    cfg.frames.sensor = a.lidar;
    cfg.frames.sensor.sensor = a.sensor;
    cfg.frames.topic = a.topic;
    RunFiles files;
    lidarFramesInputs(files, a.points);
    files.input(a.sensor, "--sensor");
    if (isLidarPresetFile(a.sensor)) {  // and what it reads: its base, its pattern file
        const LidarSpec spec = lidarSpec(a.sensor);
        if (isLidarPresetFile(spec.base)) files.input(spec.base, "--sensor");
        files.input(spec.pattern_file, "--sensor");
    }
    files.output(a.out, "--out");
    files.output(a.report, "--report");
    outsideLidarFrames(a.out, "--out", a.points);
    outsideLidarFrames(a.report, "--report", a.points);
    cfg.frames.on_scene = [&](const Scene& scene) { recordSceneInputs(files, a.scene, scene); };
    Progress bar("fit", "frames");
    RunControl control;
    control.progress = [&](long long done, long long total) { bar.update(done, total); };
    const LidarFitRunResult r = runLidarFit(cfg, control);
    {
        std::ofstream(files.stage(a.report)) << lidarFitJson(r);
        std::ofstream(files.stage(a.out)) << r.preset;
    }
    files.commit();
    say("%zu frames of the %s, %lld beams used of %lld clear beams answered; intensity scatter %.3f +/- %.3f "
        "noise sd; range sd %.4g +/- %.2g m (the preset's %.4g m)\n",
        r.frames, r.sensor.c_str(), r.fit.beams, r.clear, r.fit.scatter, r.fit.scatter_se, r.range_sd_m,
        r.range_sd_se_m, r.preset_range_sd_m);
    if (r.empty_frames > 0)
        say("  %zu empty frame%s left out (no point, or points for under a tenth of the beams the replay "
            "is sure of)\n",
            r.empty_frames, r.empty_frames == 1 ? "" : "s");
    if (r.unusable_intensities > 0)
        say("  %lld more clear beams answered with intensities not finite or not positive: left out\n",
            r.unusable_intensities);
    int misfit = 0;
    for (const SurfaceReflectanceFit& f : r.fit.surfaces) {
        const std::string name = printable(r.surface_names[size_t(f.surface)]);
        misfit += misfits(f);
        if (!f.fitted && f.candidates >= cfg.fit.min_beams)
            say("  %s: not fitted (%lld beams answered at it, fewer than %lld bright enough)\n", name.c_str(),
                f.candidates, cfg.fit.min_beams);
        else if (f.fitted)
            say("  %s: reflectance factor %.4f +/- %.2g (stat) +/- %.2g (sys), %lld beams%s\n", name.c_str(), f.factor,
                f.factor_se, f.factor_sys, f.beams,
                std::find(r.at_bound.begin(), r.at_bound.end(), f.surface) != r.at_bound.end()
                    ? " (written at the bound 0.01-10: is the scene's reflectance right?)"
                    : "");
        if (misfits(f)) say("    its intensities scatter %.3g noise sd about the fit\n", f.scatter);
    }
    if (misfit > 0)
        say("warning: %d surface%s intensities are not a factor times the replay's (scatter over %g noise sd): "
            "glossy, or the scene or sensor not the recording's; their factors explain a mean, not the surface\n",
            misfit, misfit > 1 ? "s'" : "'s", kMisfitScatter);
    say("wrote %s (the %s extended by the factors) and %s\n", a.out.c_str(), r.sensor.c_str(), a.report.c_str());
    return 0;
}

int runFit(const FitArgs& a0, const std::vector<std::string>& given)
{
    if (lidarRun(given, kLidarFitOptions, "fit")) return fitLidarFrames(a0);
    FitArgs a = a0;
    if (a.saturation.empty()) throw Error("--saturation", "is required (or --points: a 3D lidar's frames)");
    if (a.report.empty()) a.report = beside(a.out, "_report.json");
    if (a.plots.empty()) a.plots = beside(a.out, "");
    scansSource(a.laser, a.bag, a.topic);
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
    FitRunConfig fc;
    fc.model = sensorModelOption("--model", a.model);
    fc.in = FitInputsConfig{a.laser,
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
    fc.fit = a.cfg;
    fc.fit.offset_s = a.offset;
    fc.fit.estimate_offset = !a.fixed_offset;
    fc.omni = a.omni;
    fc.omni_given = a.omni_given;
    const bool omnicam = recordedSensor(a.sensor_type).omnicam();
    // Checked after what runFit checks first (a bag, the physical model) and before its work.
    if (omnicam && (!a.covariates.empty() || a.covariates_all) && a.bag.empty() && fc.model != SensorModel::Physical)
        throw Error(a.covariates_all ? "--covariates-all" : "--covariates",
                    "are a laser's beams; the omnicam has none");
    fc.on_scene = [&](const Scene& scene) { recordSceneInputs(files, a.scene, scene); };
    FitRunResult r = runFit(fc);
    if (omnicam) return finishFitOmni(a, files, r);
    a.cfg = r.used;
    const UrgNoiseFloorResult* phys = r.physical ? &*r.physical : nullptr;
    // A failed fit writes its report alone (it holds the diagnosis); a fitted one writes everything.
    if (r.fit.ok() && !(phys && !phys->ok) && !a.covariates.empty())
        writeCovariates(files.stage(a.covariates), r.inputs.log, r.fit, *r.inputs.scene, *r.inputs.surfaces,
                        r.inputs.mount, r.spec, a.covariates_all);
    writeFitOutputs(a, files, r.fit, r.inputs.sources, phys);
    const ThresholdFit& ref = r.fit.thresholds[size_t(r.fit.reference)];
    if (phys) {
        if (!phys->ok) throw Error(r.scans, r.failure + " (report: " + a.report + ")");
        say("physical model on '%s': noise floor %.4g +/- %.2g (its onset at %.5f +/- %.5f density.m)\n",
            phys->group.c_str(), phys->noise_floor.value, phys->noise_floor.se, phys->onset_column.value,
            phys->onset_column.se);
    }
    writeSensorFile(files.stage(a.out), *r.laser, r.sensor_comment + " (report: " + a.report + ")");
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
    RunFiles files;
    files.input(a.laser, "--laser");
    bagInputs(files, a.bag, "--bag");
    files.output(a.out, "--out");
    PlumeRunConfig pc{a.laser,  a.bag,
                      a.topic,  a.scene,
                      a.sensor, {parseRangeUnit(a.unit), a.lenient},
                      a.cfg,    [&](const Scene& scene) { recordSceneInputs(files, a.scene, scene); }};
    const PlumeRunResult run = runPlumeFit(pc);
    const PlumeFitResult& r = run.fit;
    const std::string& source = run.source;
    writePlumeFitJson(files.stage(a.out), r, a.cfg, source, a.scene);
    say("%zu beams crossed a plume (%zu bad lines skipped)\n", r.obs.size(), run.skipped);
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
                         "Saturation CSV: time_s,saturation[,patches] (as `saturation` writes it); not with --points");
    c->add_option("--out", a->out,
                  "Sensor file to write (TOML, for `scan --sensor-file`); with --points the lidar preset extended by "
                  "the surfaces' factors (for `scan --sensor`)")
        ->required();
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
    // An empty name would be taken as no option: the default path, or nothing written.
    c->add_option("--report", a->report, "JSON report (default: OUT's name + _report.json)")->check(nonEmpty());
    c->add_option("--plots", a->plots, "Plot path prefix: PREFIX_fig5.png, PREFIX_fig9.png (default: OUT's name)")
        ->check(nonEmpty());
    c->add_option("--aligned", a->aligned, "Also write the aligned streams (CSV)")->check(nonEmpty());
    c->add_option("--covariates", a->covariates,
                  "Also write per-beam, per-scan covariates from the scene (CSV; needs --scene)")
        ->check(nonEmpty());
    c->add_flag("--covariates-all", a->covariates_all, "Covariates for every beam, not only the groups'");
    c->add_option(
        "--points", a->points,
        "Or a 3D lidar's frames: a folder as `scan --points` writes it (frames.csv, a PCD or PLY a frame, "
        "with ring, time and intensity fields) or a ROS 2 or ROS 1 bag of PointCloud2 frames (--topic); --sensor "
        "names the lidar, --scene its scene; --out the "
        "preset extended by each surface's reflectance factor");
    c->add_option("--returns", a->lidar.returns, "3D lidar: the frames' return mode (default: the preset's)");
    c->add_option("--columns", a->lidar.columns, "3D lidar: columns a turn (default: the preset's)")->check(positive());
    c->add_option("--rate", a->lidar.rate_hz, "3D lidar: spin rate [Hz] (default: the preset's)")->check(positive());
    c->callback([a, c, &run] {
        std::vector<std::string> given;
        for (const CLI::Option* o : c->get_options())
            if (o->count() > 0) given.push_back(o->get_name());
        run = [a, given] { return runFit(*a, given); };
    });
}

}  // namespace smokescan::cli
