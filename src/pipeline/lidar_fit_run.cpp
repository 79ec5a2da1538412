// `smokescan fit --points` as one library call (pipeline/lidar_fit_run.hpp).
#include "smokescan/pipeline/lidar_fit_run.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

#include "smokescan/core/format.hpp"

namespace smokescan {
namespace {

/// The clear beams' range residuals' robust sd (1.4826·MAD) and its count, over both folds.
std::pair<double, size_t> rangeSd(const LidarTally& t)
{
    std::vector<float> r;
    for (int k : {0, 1})
        for (const std::vector<float>& ring : t.fold(k).residual_m) r.insert(r.end(), ring.begin(), ring.end());
    if (r.empty()) return {NAN, 0};
    auto median = [](std::vector<float>& v) {
        std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
        return double(v[v.size() / 2]);
    };
    const double m = median(r);
    std::vector<float> dev(r.size());
    std::transform(r.begin(), r.end(), dev.begin(), [&](float x) { return float(std::abs(x - m)); });
    return {1.4826 * median(dev), r.size()};
}

nlohmann::json num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

}  // namespace

std::string fittedLidarPreset(const LidarFitResult& fit, const std::vector<std::string>& surface_names,
                              const LidarSpec& fitted, const std::string& base)
{
    LidarExtensions e = fitted.extensions;
    for (const SurfaceReflectanceFit& f : fit.surfaces) {
        if (!f.fitted || f.surface < 0 || size_t(f.surface) >= surface_names.size()) continue;
        const std::string& name = surface_names[size_t(f.surface)];
        auto it = std::find_if(e.surfaces.begin(), e.surfaces.end(),
                               [&](const LidarSurfaceExtension& x) { return x.name == name; });
        if (it == e.surfaces.end()) it = e.surfaces.insert(e.surfaces.end(), {name, 1.0});
        // The replay already had its factor: the fitted one is on top of it.
        it->reflectance_factor = std::clamp(it->reflectance_factor * f.factor, 0.01, 10.0);
    }
    std::string name = fitted.name;
    if (name.size() < 9 || name.compare(name.size() - 9, 9, "-extended") != 0) name += "-extended";
    return "# The " + fitted.name +
        " extended by smokescan fit --points: each surface's reflectance factor from the recorded "
        "intensities.\n# Scan with it: smokescan scan SCENE --sensor this_file.toml\nname = " +
        tomlQuoted(name) + "\nbase = " + tomlQuoted(base) + "\n" + lidarExtensionsToml(e);
}

LidarFitRunResult runLidarFit(const LidarFitRunConfig& cfg, const RunControl& control)
{
    LidarFitRunResult out;
    LidarFramesConfig frames = cfg.frames;
    frames.intensities = true;
    tallyLidarFrames(frames, 1, control, [&](const TalliedFrames& t) {
        const LidarSpec& spec = t.run.spec();
        out.fit = fitLidarIntensities(t.tally.intensities(), cfg.fit);
        for (const Surface& sf : t.scene.surfaces) out.surface_names.push_back(sf.name);
        out.sensor = spec.name;
        out.returns = returnModeName(t.run.mode());
        out.scene = t.scene.source;
        out.frames = t.tally.frames();
        out.clear = (long long)t.tally.intensities().size();
        const auto [sd, n] = rangeSd(t.tally);
        out.range_sd_m = sd;
        out.range_sd_se_m = n > 0 ? 1.166 * sd / std::sqrt(double(n)) : NAN;
        out.preset_range_sd_m = spec.range_sigma_m;
        out.pose_mismatch_m = t.pose_mismatch_m;
        out.pose_mismatch_deg = t.pose_mismatch_deg;
        out.preset = fittedLidarPreset(out.fit, out.surface_names, spec, t.base);
    });
    return out;
}

std::string lidarFitJson(const LidarFitRunResult& r)
{
    nlohmann::json j;
    j["sensor"] = r.sensor;
    j["returns"] = r.returns;
    j["scene"] = r.scene;
    j["frames"] = r.frames;
    j["clear_beams_answered"] = r.clear;
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
        s.push_back({{"surface", name},
                     {"fitted", f.fitted},
                     {"beams", f.beams},
                     {"reflectance_factor", f.fitted ? num(f.factor) : nullptr},
                     {"reflectance_factor_se", f.fitted ? num(f.factor_se) : nullptr},
                     {"reflectance_factor_sys", f.fitted ? num(f.factor_sys) : nullptr},
                     {"intensity_scatter", f.fitted ? num(f.scatter) : nullptr}});
    }
    j["surfaces"] = s;
    j["extended_preset"] = r.preset;
    return j.dump(2) + "\n";
}

}  // namespace smokescan
