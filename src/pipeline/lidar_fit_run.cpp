// `smokescan fit --points` as one library call (pipeline/lidar_fit_run.hpp).
#include "smokescan/pipeline/lidar_fit_run.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <unordered_map>

#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"

namespace smokescan {
namespace {

nlohmann::json num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

/// Multiplies the factor `name` has in `e` (1 when none: a table is added) by k, held within
/// 0.01–10. @return the product before it was held
double multiplyFactor(LidarExtensions& e, const std::string& name, double k)
{
    auto it = std::find_if(e.surfaces.begin(), e.surfaces.end(),
                           [&](const LidarSurfaceExtension& x) { return x.name == name; });
    if (it == e.surfaces.end()) it = e.surfaces.insert(e.surfaces.end(), {name, 1.0});
    const double product = it->reflectance_factor * k;
    it->reflectance_factor = std::clamp(product, 0.01, 10.0);
    return product;
}

}  // namespace

std::string fittedLidarPreset(const LidarFitResult& fit, const std::vector<std::string>& surface_names,
                              const LidarSpec& fitted, const std::string& base, std::vector<int>* at_bound)
{
    std::string too_long;
    LidarExtensions e = fitted.extensions;
    std::string clamped;
    for (const SurfaceReflectanceFit& f : fit.surfaces) {
        if (!f.fitted || f.surface < 0 || size_t(f.surface) >= surface_names.size()) continue;
        const std::string& name = surface_names[size_t(f.surface)];
        if (name.size() > lidar_limits::kSurfaceName) {  // a preset cannot name it
            too_long += " " + printable(name, 60);
            continue;
        }
        // The replay already had its factor: the fitted one is on top of it.
        const double k = multiplyFactor(e, name, f.factor);
        if (k < 0.01 || k > 10) {
            if (at_bound) at_bound->push_back(f.surface);
            clamped += " " + printable(name, 80) + " (" + fmt("%.4g", k) + ")";  // (escaped: on one line)
        }
    }
    std::string o = "# The " + fitted.name +
        " extended by smokescan fit --points: each surface's reflectance factor from the recorded "
        "intensities.\n# Scan with it: smokescan scan SCENE --sensor this_file.toml\n";
    if (!clamped.empty())
        o += "# Held at the bounds 0.01-10 (the scene's reflectance is far off there):" + clamped + "\n";
    if (!too_long.empty()) o += "# Not written: names longer than a preset holds (4096 bytes):" + too_long + "\n";
    return o + "name = " + tomlQuoted(extendedPresetName(fitted.name)) + "\nbase = " + tomlQuoted(base) + "\n" +
        lidarExtensionsToml(e);
}

namespace {

/// The spec with each fitted surface's factor (relative to the spec's own) multiplied into its extensions.
LidarSpec withFactors(LidarSpec spec, const LidarFitResult& fit, const std::vector<std::string>& names)
{
    for (const SurfaceReflectanceFit& f : fit.surfaces)
        if (f.fitted) multiplyFactor(spec.extensions, names[size_t(f.surface)], f.factor);
    return spec;
}

/// The factor a surface has in `spec` (1 when it has none).
double factorIn(const LidarSpec& spec, const std::string& name)
{
    for (const LidarSurfaceExtension& x : spec.extensions.surfaces)
        if (x.name == name) return x.reflectance_factor;
    return 1;
}

}  // namespace

LidarFitRunResult runLidarFit(const LidarFitRunConfig& cfg, const RunControl& control)
{
    if (cfg.max_replays < 1 || cfg.max_replays > 20) throw Error("lidar fit", "max_replays must lie in 1–20");
    LidarFitRunResult out;
    LidarFramesConfig frames = cfg.frames;
    frames.intensities = true;
    frames.keep_points = cfg.max_replays > 1;
    size_t scene_surfaces = 0;
    frames.on_scene = [&](const Scene& scene) {
        scene_surfaces = scene.surfaces.size();
        if (cfg.frames.on_scene) cfg.frames.on_scene(scene);
    };
    frames.on_run = [&](const LidarRun& run) {  // room in the written preset for every surface
        if (cfg.frames.on_run) cfg.frames.on_run(run);
        if (run.spec().extensions.surfaces.size() + scene_surfaces > lidar_limits::kExtensionSurfaces)
            throw Error("--sensor",
                        fmt("the %s's %zu surface extensions and the scene's %zu surfaces could pass the "
                            "%zu a preset holds",
                            run.spec().name.c_str(), run.spec().extensions.surfaces.size(), scene_surfaces,
                            lidar_limits::kExtensionSurfaces));
    };
    tallyLidarFrames(frames, 1, control, [&](const TalliedFrames& t) {
        const LidarSpec& given = t.run.spec();
        for (const Surface& sf : t.scene.surfaces) out.surface_names.push_back(sf.name);
        // Surfaces of one name are one extension: fitted as one, under the first's index.
        std::vector<int> first(out.surface_names.size());
        std::unordered_map<std::string, int> seen;
        for (size_t k = 0; k < first.size(); ++k) first[k] = seen.emplace(out.surface_names[k], int(k)).first->second;
        auto byName = [&](std::vector<LidarIntensitySample> s) {
            for (LidarIntensitySample& x : s) x.surface = first[size_t(x.surface)];
            return s;
        };
        LidarFitResult fit = fitLidarIntensities(byName(t.tally.intensities()), cfg.fit);
        LidarSpec spec = given;  // the replay's: the given preset with the factors found so far
        const LidarTally* last = &t.tally;  // the tally of the last replay
        std::unique_ptr<LidarTally> again_tally;
        // Again against a replay with the factors found, until the steps are within their errors.
        for (out.replays = 1; out.replays < cfg.max_replays; ++out.replays) {
            const bool settled =
                std::all_of(fit.surfaces.begin(), fit.surfaces.end(), [](const SurfaceReflectanceFit& f) {
                    return !f.fitted || std::abs(f.factor - 1) <= 0.1 * std::hypot(f.factor_se, f.factor_sys);
                });
            if (settled) break;
            spec = withFactors(spec, fit, out.surface_names);
            const LidarScanner again(t.scene, t.run.surfaces(), t.run.mount(), spec, t.run.mode(), 1);
            again_tally = std::make_unique<LidarTally>(again.pattern(), spec.channels(), returnTolerance_m(spec),
                                                       spec.range_max_m);
            again_tally->keepIntensities(true);
            for (size_t k = 0; k < t.recorded.size(); ++k) {
                checkCancel(control);
                again_tally->add(again.expected(t.recorded[k].first, true), t.recorded[k].second, int(k % 2));
            }
            last = again_tally.get();
            fit = fitLidarIntensities(byName(last->intensities()), cfg.fit);
        }
        // The last step on the factors it was taken from: each surface's factor against the given preset.
        for (SurfaceReflectanceFit& f : fit.surfaces) {
            if (!f.fitted) continue;
            const std::string& name = out.surface_names[size_t(f.surface)];
            const double before = factorIn(spec, name) / factorIn(given, name);
            f.factor *= before, f.factor_se *= before, f.factor_sys *= before;
        }
        out.fit = fit;
        out.sensor = given.name;
        out.returns = returnModeName(t.run.mode());
        out.scene = t.scene.source;
        out.points = cfg.frames.points;
        out.topic = t.topic;
        out.frames = t.tally.frames();
        // The clear beams and their ranges' spread as the last replay sees them (a surface's
        // factor moves where its echo reads in the smoke).
        out.clear = (long long)last->intensities().size();
        out.unusable_intensities = last->unusableIntensities();
        const double sd = robustResidualSd({&last->fold(0).residual_m, &last->fold(1).residual_m});
        size_t n = 0;
        for (int k : {0, 1})
            for (const std::vector<float>& ring : last->fold(k).residual_m) n += ring.size();
        out.range_sd_m = sd;
        out.range_sd_se_m = n > 0 ? 1.166 * sd / std::sqrt(double(n)) : NAN;
        out.preset_range_sd_m = given.range_sigma_m;
        out.pose_mismatch_m = t.pose_mismatch_m;
        out.pose_mismatch_deg = t.pose_mismatch_deg;
        out.empty_frames = t.empty_frames;
        out.preset = fittedLidarPreset(out.fit, out.surface_names, given, t.base, &out.at_bound);
    });
    return out;
}

std::string lidarFitJson(const LidarFitRunResult& r)
{
    nlohmann::json j;
    j["sensor"] = r.sensor;
    j["returns"] = r.returns;
    // Names as the user gave them; bytes JSON cannot hold (not UTF-8) and controls as \xNN.
    j["scene"] = printableWhole(r.scene);
    j["points"] = printableWhole(r.points);
    j["topic"] = r.topic.empty() ? nlohmann::json() : nlohmann::json(printableWhole(r.topic));
    j["frames"] = r.frames;
    j["empty_frames_left_out"] = r.empty_frames;
    j["replays"] = r.replays;
    j["clear_beams_answered"] = r.clear;
    j["unusable_intensities"] = r.unusable_intensities;
    j["beams_used"] = r.fit.beams;
    j["intensity_scatter"] = num(r.fit.scatter);
    j["intensity_scatter_se"] = num(r.fit.scatter_se);
    j["range_sd_m"] = num(r.range_sd_m);
    j["range_sd_se_m"] = num(r.range_sd_se_m);
    j["preset_range_sd_m"] = num(r.preset_range_sd_m);
    j["pose_mismatch_m"] = num(r.pose_mismatch_m);
    j["pose_mismatch_deg"] = num(r.pose_mismatch_deg);
    nlohmann::json s = nlohmann::json::array();
    for (const SurfaceReflectanceFit& f : r.fit.surfaces) {
        const std::string name =
            f.surface >= 0 && size_t(f.surface) < r.surface_names.size() ? r.surface_names[size_t(f.surface)] : "";
        s.push_back(
            {{"surface", name},
             {"fitted", f.fitted},
             {"beams", f.beams},
             {"reflectance_factor", f.fitted ? num(f.factor) : nullptr},
             {"reflectance_factor_se", f.fitted ? num(f.factor_se) : nullptr},
             {"reflectance_factor_sys", f.fitted ? num(f.factor_sys) : nullptr},
             {"intensity_scatter", f.fitted ? num(f.scatter) : nullptr},
             {"misfit", misfits(f)},
             {"written_at_bound", std::find(r.at_bound.begin(), r.at_bound.end(), f.surface) != r.at_bound.end()}});
    }
    j["surfaces"] = s;
    j["extended_preset"] = r.preset;
    return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

}  // namespace smokescan
