#include "smokescan/calib/calibration.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <set>
#include <tuple>

#include <fstream>
#include <sstream>

#include "smokescan/camera/saturation_render.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/io/text_input.hpp"
#include "smokescan/render/renderer.hpp"
#include "smokescan/scene/mesh.hpp"
#include "smokescan/scene/surfaces.hpp"

namespace smokescan {
Scene uniformSmokeScene(const Scene& scene, double density)
{
    Aabb bounds;
    for (const auto& s : scene.surfaces)
        for (const Vec3& p : tessellate(s).points_m) bounds.extend(p);
    if (bounds.empty()) throw Error(scene.source, "has no surfaces to fill with smoke");
    Medium medium = Medium::preset("theatrical_fog");
    for (const auto& v : scene.volumes)
        if (v.role == SmokeRole::Regional) {
            medium = v.medium;
            break;
        }
    const double h = (bounds.hi - bounds.lo).maxCoeff() / 128.0;
    Scene out = scene;
    SmokeVolume v;
    v.name = "calibration_smoke";
    v.medium = medium;
    v.source = std::make_shared<const DensityGrid>(DensityGrid::box(bounds.lo, bounds.hi, 1.0, h));
    v.timeline = DensityTimeline::constant(density);
    out.volumes = {v};
    return out;
}

namespace {

SaturationPoint toPoint(double rho, const SaturationStats& s, double se)
{
    // The converged measurement's standard error (camera noise and the field's); a floor for
    // what the curve cannot be asked to resolve.
    return {rho, s.mean, std::max(1e-4, se)};
}

}  // namespace

/// The light's mixing at each density, from the patches' colours (light_mixing.hpp); needs density 0.
static void measureMixing(const std::vector<double>& densities,
                          const std::vector<std::map<std::string, std::array<double, 3>>>& colours,
                          CalibrationResult& res)
{
    if (densities.empty() || densities.front() != 0 || colours.front().size() < 2) return;
    std::vector<std::array<double, 3>> clear;
    for (const auto& [name, c] : colours.front()) clear.push_back(c);
    for (size_t k = 0; k < densities.size(); ++k) {
        std::vector<std::array<double, 3>> seen;
        for (const auto& [name, c] : colours[k]) seen.push_back(c);
        if (seen.size() == clear.size()) res.mixing.push_back(measureLightMixing(densities[k], clear, seen));
    }
    std::tie(res.mixing_b, res.mixing_b_se) = extinctionPath(res.mixing);
}

/// Each patch alone under the joint fit's light: the drifting light's when it converged.
static void fitPatchesUnderTheJointLight(double gamma, CalibrationResult& res)
{
    const bool drift = res.drift.converged && !res.drift.std_error.empty();
    const ColourMixFit& joint = drift ? res.drift : res.mix;
    if (joint.std_error.empty()) return;
    res.patch_mix_light = drift ? "drifting" : "one colour";
    res.patch_mix = fitPatchesUnderLight(res.patch_points, gamma, joint.curve);
}

/// The sweep over densities in ascending order.
static CalibrationResult calibrateSorted(const Scene& scene0, const CalibrateConfig& cfg,
                                         const std::function<void(int, int)>& progress,
                                         std::chrono::steady_clock::time_point t0);

CalibrationResult calibrate(const Scene& scene0, const CalibrateConfig& cfg,
                            const std::function<void(int, int)>& progress)
{
    const auto t0 = std::chrono::steady_clock::now();
    if (scene0.cameras.empty()) throw Error(scene0.source, "the scene has no camera to calibrate with");
    for (double d : cfg.densities)
        if (!(d >= 0) || !std::isfinite(d)) throw Error("--densities", "densities must be finite and >= 0");
    if (std::set<double>(cfg.densities.begin(), cfg.densities.end()).size() < 4)
        throw Error("--densities",
                    "needs at least 4 distinct densities to fit 3 parameters, got " +
                        std::to_string(std::set<double>(cfg.densities.begin(), cfg.densities.end()).size()));
    CalibrateConfig sorted_cfg = cfg;  // ascending: the curves' floors are tabulated in density order
    std::sort(sorted_cfg.densities.begin(), sorted_cfg.densities.end());
    return calibrateSorted(scene0, sorted_cfg, progress, t0);
}

static CalibrationResult calibrateSorted(const Scene& scene0, const CalibrateConfig& cfg,
                                         const std::function<void(int, int)>& progress,
                                         std::chrono::steady_clock::time_point t0)
{
    Scene scene = uniformSmokeScene(scene0, 0.0);
    const SurfaceSet surfaces(scene);
    CalibrationResult res;
    const int n = int(cfg.densities.size());
    std::vector<std::map<std::string, std::array<double, 3>>> colours;  // each patch's, per density
    for (int k = 0; k < n; ++k) {
        const double rho = cfg.densities[size_t(k)];
        scene.volumes[0].timeline = DensityTimeline::constant(rho);
        RenderConfig rc;
        rc.width = cfg.width;
        rc.height = cfg.height;
        rc.seed = cfg.seed + uint64_t(k);
        rc.camera = cfg.camera;
        rc.progress = false;
        rc.watch = cfg.watch;
        const TargetSaturation m = measureConvergedSaturation(scene, surfaces, rc, cfg.target_prefix, cfg.field);
        if (cfg.watch && cfg.watch->stop) throw Error("calibrate", "stopped");
        res.points.push_back(toPoint(rho, m.all, m.se));
        for (const auto& [name, s] : m.patches) res.patches[name].push_back(toPoint(rho, s, m.patch_se.at(name)));
        res.spp.push_back(m.spp);
        colours.push_back(m.patch_colour);
        res.rel_error.push_back(m.rel_error);
        res.floor.push_back(m.floor);
        for (const auto& [name, st] : m.patches) {
            const std::string& patch = name;  // a structured binding cannot be captured (C++17)
            auto it = std::find_if(res.patch_points.begin(), res.patch_points.end(),
                                   [&](const PatchPoints& pp) { return pp.name == patch; });
            if (it == res.patch_points.end()) {
                res.patch_points.push_back(PatchPoints{name, 0.0, {}, {}, m.patch_colour.at(name), {}});
                it = res.patch_points.end() - 1;
            }
            it->points.push_back(toPoint(rho, st, m.patch_se.at(name)));
            it->floor.push_back(m.patch_floor.at(name));
            it->weight += m.patch_share.at(name) / n;
            if (rho == 0 || it->brightness.empty()) {
                it->clear_colour = m.patch_colour.at(name);
                it->brightness = m.patch_brightness.at(name);
            }
        }
        if (progress) progress(k + 1, n);
    }
    measureMixing(cfg.densities, colours, res);
    CurveFitConfig fit = cfg.fit;  // the camera's noise floor over the sweep: derived, fixed
    double floor_sum = 0;
    for (double f : res.floor) floor_sum += f;
    fit.floor = res.floor.empty() ? 0.0 : floor_sum / double(res.floor.size());
    res.fit = fitSaturationCurve(res.points, fit);
    for (const auto& [name, pts] : res.patches) {
        try {
            res.patch_fits[name] = fitSaturationCurve(pts, fit);
        } catch (const Error&) {
            // A patch whose saturation does not vary (e.g. a grey one) has no curve of its own.
        }
    }
    const double rho_max = *std::max_element(cfg.densities.begin(), cfg.densities.end());
    try {
        res.mix = fitColourMix(res.patch_points, cfg.fit.gamma);
        if (!res.mix.std_error.empty())
            std::tie(res.mix_threshold_density, res.mix_threshold_density_se) =
                res.mix.invert(cfg.threshold_saturation, rho_max);
    } catch (const Error& e) {
        // Too few points, or a sweep that never reaches the threshold: the effective curve stands alone.
        res.mix.message = e.what();
    }
    try {
        res.drift = fitColourMix(res.patch_points, cfg.fit.gamma, true);
        if (!res.drift.std_error.empty())
            std::tie(res.drift_threshold_density, res.drift_threshold_density_se) =
                res.drift.invert(cfg.threshold_saturation, rho_max);
    } catch (const Error& e) {
        res.drift.message = e.what();
    }
    fitPatchesUnderTheJointLight(cfg.fit.gamma, res);
    for (size_t k = 0; k < res.rel_error.size(); ++k)
        if (!(res.rel_error[k] <= 0.5))
            throw Error("calibrate",
                        "the target's radiance is too uncertain at density " + std::to_string(cfg.densities[k]) +
                            " (relative error " + std::to_string(res.rel_error[k]) + " over 0.5" +
                            "): more --spp or --max-batches, or a lower density");
    if (!res.fit.converged) return res;  // the caller reports the fit's failure
    if (!(res.fit.curve.a <= 1e3 && res.fit.curve.b >= 1))
        throw Error("calibrate",
                    "the curve is degenerate (a = " + std::to_string(res.fit.curve.a) +
                        ", b = " + std::to_string(res.fit.curve.b) +
                        " per density unit): the sweep does not constrain it; check --densities");
    double rho = 0, se = 0;
    try {
        std::tie(rho, se) = res.fit.invert(cfg.threshold_saturation);
    } catch (const Error& e) {
        throw Error("calibrate", std::string("the curve never reads the threshold: ") + e.what());
    }
    const double rho_min = cfg.densities.front();
    if (!(rho >= rho_min && rho <= rho_max))
        throw Error("calibrate",
                    "saturation " + std::to_string(cfg.threshold_saturation) + " falls at density " +
                        std::to_string(rho) + ", outside the sweep [" + std::to_string(rho_min) + ", " +
                        std::to_string(rho_max) + "]: an extrapolation; widen --densities");
    res.threshold_density = rho;
    res.threshold_density_se = se;
    res.penetration_power = rho * cfg.path_m;
    res.penetration_power_se = se * cfg.path_m;
    res.engine_unit_factor = rho / cfg.paper_density;
    res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
}

namespace {
nlohmann::json fitJson(const CurveFitResult& f, const std::vector<SaturationPoint>& pts)
{
    nlohmann::json j;
    j["parameters"] = {
        {"S0", f.curve.S0}, {"a", f.curve.a}, {"b", f.curve.b}, {"gamma", f.curve.gamma}, {"floor", f.curve.floor}};
    j["std_errors"] = {{"S0", f.std_error[0]}, {"a", f.std_error[1]}, {"b", f.std_error[2]}};
    nlohmann::json cov = nlohmann::json::array();
    for (int r = 0; r < 3; ++r) cov.push_back({f.covariance(r, 0), f.covariance(r, 1), f.covariance(r, 2)});
    j["covariance"] = cov;
    j["covariance_order"] = {"S0", "a", "b"};
    j["converged"] = f.converged;
    j["chi2"] = f.chi2;
    j["dof"] = f.dof;
    j["r2"] = f.r2;
    j["solver"] = f.message;
    nlohmann::json p = nlohmann::json::array();
    for (const auto& q : pts)
        p.push_back({{"density", q.density}, {"saturation", q.saturation}, {"std_error", q.sigma}});
    j["points"] = p;
    return j;
}
nlohmann::json mixFitJson(const ColourMixFit& f, const std::vector<PatchPoints>& pts)
{
    nlohmann::json j;
    j["b"] = f.curve.b;
    j["b_std_error"] = f.std_error.empty() ? 0.0 : f.std_error[0];
    j["airlight_rgb"] = f.curve.airlight;
    j["airlight_std_error_gb"] = {f.std_error.size() > 2 ? f.std_error[1] : 0.0,
                                  f.std_error.size() > 2 ? f.std_error[2] : 0.0};
    if (f.curve.kappa > 0) {  // the drifting light
        j["airlight_dense_rgb"] = f.curve.airlight_dense;
        j["kappa"] = f.curve.kappa;
    }
    for (size_t p = 0; p < f.curve.target.size(); ++p) {
        nlohmann::json t;
        t["colour_rgb"] = f.curve.target[p];
        t["weight"] = f.curve.weight[p];
        t["brightness_classes"] = pts[p].brightness;
        t["clear_colour_measured"] = pts[p].clear_colour;
        t["chi2"] = f.patch_chi2[p];
        nlohmann::json res = nlohmann::json::array();
        for (size_t i = 0; i < pts[p].points.size(); ++i) {
            const auto& q = pts[p].points[i];
            res.push_back({{"density", q.density},
                           {"saturation", q.saturation},
                           {"std_error", q.sigma},
                           {"noise_floor", pts[p].floor[i]},
                           {"curve", f.curve.patch(p, q.density)}});
        }
        t["points"] = res;
        j["patches"][f.curve.names[p]] = t;
    }
    j["chi2"] = f.chi2;
    j["dof"] = f.dof;
    j["converged"] = f.converged;
    j["solver"] = f.message;
    return j;
}

nlohmann::json mixJson(const CalibrationResult& r)
{
    nlohmann::json j;
    j["model"] =
        "x_c = l_c*T + A_c*(1 - T), T = exp(-b*rho), y_c = x_c^gamma; S = mean over the brightness classes of "
        "1 - E[min y']/E[max y'], y' = y + normal noise of relative sd floor*sqrt(pi)/3";
    j["model_doc"] = "docs/calibration.md";
    j["joint"] = mixFitJson(r.mix, r.patch_points);
    const PatchExtinctions& pe = r.patch_mix;
    for (const auto& pp : r.patch_points)
        if (pe.fits.count(pp.name)) j["per_patch"][pp.name] = mixFitJson(pe.fits.at(pp.name), {pp});
    if (pe.dof > 0) {
        j["per_patch_light"] = "held at the joint fit's (" + r.patch_mix_light +
            "); each patch's b and colour free; b's errors leave out the light's (common to all)";
        j["per_patch_b_mean"] = pe.b_mean;
        j["per_patch_b_chi2"] = pe.chi2;
        j["per_patch_b_dof"] = pe.dof;
        j["per_patch_b_p_value"] = pe.p_value;
    }
    j["threshold_density"] = r.mix_threshold_density;
    j["threshold_density_std_error"] = r.mix_threshold_density_se;
    if (!r.drift.std_error.empty()) {
        nlohmann::json d;
        d["model"] =
            "the colour-mixing curve with A_c(rho) = w*airlight + (1 - w)*airlight_dense, w = exp(-kappa*rho); "
            "b, kappa and the light's colours trade off: only the threshold is meant";
        d["joint"] = mixFitJson(r.drift, r.patch_points);
        d["threshold_density"] = r.drift_threshold_density;
        d["threshold_density_std_error"] = r.drift_threshold_density_se;
        j["drifting_light"] = d;
    }
    return j;
}

}  // namespace

std::string calibrationJson(const CalibrationResult& r, const CalibrateConfig& cfg, const std::string& scene_source)
{
    nlohmann::json j;
    j["model"] = "S(rho) = sqrt((1 - (1 - S0 / (1 + a*(exp(b*rho) - 1)))^gamma)^2 + floor^2)";
    j["model_doc"] = "docs/calibration.md";
    j["combined"] = fitJson(r.fit, r.points);
    for (const auto& [name, f] : r.patch_fits) j["patches"][name] = fitJson(f, r.patches.at(name));
    if (!r.mix.std_error.empty()) j["colour_mix"] = mixJson(r);
    if (!r.mixing.empty()) {
        nlohmann::json m;
        m["model"] =
            "each patch's linear colour x_p = l_p*T + A*(1 - T), l_p its clear-air colour: T and A per density";
        m["b"] = r.mixing_b;
        m["b_std_error"] = r.mixing_b_se;
        for (const auto& q : r.mixing)
            m["points"].push_back({{"density", q.density},
                                   {"transmittance", q.transmittance},
                                   {"transmittance_std_error", q.transmittance_se},
                                   {"scattered_rgb", q.scattered},
                                   {"rms_relative", q.rms}});
        j["light_mixing"] = m;
    }
    for (const auto& pp : r.patch_points) {  // the measurement itself, for any other model
        nlohmann::json m;
        m["weight"] = pp.weight;
        m["clear_colour"] = pp.clear_colour;
        m["brightness_classes"] = pp.brightness;
        for (size_t i = 0; i < pp.points.size(); ++i)
            m["points"].push_back({{"density", pp.points[i].density},
                                   {"saturation", pp.points[i].saturation},
                                   {"std_error", pp.points[i].sigma},
                                   {"noise_floor", pp.floor[i]}});
        j["measured_patches"][pp.name] = m;
    }
    j["threshold"] = {{"saturation", cfg.threshold_saturation},
                      {"density", r.threshold_density},
                      {"density_std_error", r.threshold_density_se},
                      {"path_m", cfg.path_m},
                      {"penetration_power_density_m", r.penetration_power},
                      {"penetration_power_std_error", r.penetration_power_se},
                      {"paper_density", cfg.paper_density},
                      {"engine_unit_factor", r.engine_unit_factor},
                      {"engine_unit_factor_meaning", "smokescan density units per unit of the paper's engine density"}};
    j["render"] = {{"scene", printableWhole(scene_source)},
                   {"batch_spp", cfg.field.batch_spp},
                   {"spp_per_target_pixel", r.spp},
                   {"rel_error", cfg.field.rel_error},
                   {"rel_error_reached", r.rel_error},
                   {"field_degree", cfg.field.degree},
                   {"width", cfg.width},
                   {"height", cfg.height},
                   {"seed", cfg.seed},
                   {"densities", cfg.densities},
                   {"camera", cfg.camera},
                   {"target_prefix", cfg.target_prefix},
                   {"exposure", "the scene camera's sensor (auto: average metering)"},
                   {"seconds", r.seconds}};
    return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
}

void writeCalibrationJson(const std::string& path, const CalibrationResult& r, const CalibrateConfig& cfg,
                          const std::string& scene_source)
{
    AtomicFile f(path);
    f.stream() << calibrationJson(r, cfg, scene_source) << '\n';
    f.commit();
}

const std::vector<std::pair<std::string, std::string>>& builtinCalibrationTable();  // generated

CurveFitResult readCalibrationJson(const std::string& path_or_name, const std::string& patch)
{
    std::string text, where = path_or_name;
    for (const auto& [name, t] : builtinCalibrationTable())
        if (name == path_or_name) {
            text = t;
            where = "builtin:" + name;
        }
    if (text.empty()) {
        struct stat st {};
        if (::stat(path_or_name.c_str(), &st) != 0) throw Error(path_or_name, "no such file or built-in calibration");
        text = readTextInput(path_or_name, "calibration file");
    }
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
        const nlohmann::json& f = patch.empty() ? j.at("combined") : j.at("patches").at(patch);
        CurveFitResult r;
        const auto& p = f.at("parameters");
        r.curve.S0 = p.at("S0").get<double>();
        r.curve.a = p.at("a").get<double>();
        r.curve.b = p.at("b").get<double>();
        r.curve.gamma = p.at("gamma").get<double>();
        r.curve.floor = p.value("floor", 0.0);
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                r.covariance(a, b) = f.at("covariance").at(size_t(a)).at(size_t(b)).get<double>();
        for (int k = 0; k < 3; ++k) r.std_error[size_t(k)] = std::sqrt(std::max(0.0, r.covariance(k, k)));
        r.converged = f.at("converged").get<bool>();
        r.chi2 = f.value("chi2", 0.0);
        r.dof = f.value("dof", 0);
        const double s_star = j.contains("threshold") ? j["threshold"].value("saturation", 0.0) : 0.0;
        if (s_star > 0 && r.curve.floor >= s_star)
            throw Error(where,
                        "the noise floor " + std::to_string(r.curve.floor) +
                            " is at or above the threshold saturation " + std::to_string(s_star) +
                            ": the threshold is never reached");
        if (s_star > 0 && !(r.curve(0.0) > s_star))
            throw Error(where,
                        "clear air reads saturation " + std::to_string(r.curve(0.0)) + ", not above the threshold " +
                            std::to_string(s_star) + ": the threshold is never reached");
        if (!(r.curve.S0 > 0 && r.curve.S0 <= 1 && r.curve.a > 0 && r.curve.a <= 1e3 && r.curve.b >= 1 &&
              r.curve.b <= 1e6 && r.curve.gamma >= 0.1 && r.curve.gamma <= 10 && r.curve.floor >= 0 &&
              r.curve.floor < 0.5 && r.curve.floor < r.curve(0.0)))
            throw Error(where,
                        "calibration parameters out of range (S0 in (0, 1], a in (0, 1e3], b in [1, 1e6] "
                        "per density unit, gamma in [0.1, 10], floor in [0, 0.5) and below S(0))");
        for (int k = 0; k < 3; ++k)
            if (!(std::isfinite(r.covariance(k, k)) && r.covariance(k, k) >= 0))
                throw Error(where, "the calibration's covariance has a bad diagonal");
        if (!r.converged) throw Error(where, "the calibration's fit did not converge: refit it");
        return r;
    } catch (const nlohmann::json::out_of_range& e) {
        if (!patch.empty() && j.is_object() && !(j.contains("patches") && j["patches"].contains(patch)))
            throw Error(where, "has no patch '" + patch + "'");
        throw Error(where, std::string("not a smokescan calibration: ") + e.what());
    } catch (const nlohmann::json::exception& e) {
        throw Error(where, std::string("not a smokescan calibration: ") + e.what());
    }
}

}  // namespace smokescan
