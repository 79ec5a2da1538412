#include "smokescan/calib/calibration.hpp"

#include <sys/stat.h>

#include <chrono>
#include <cmath>
#include <iomanip>
#include <nlohmann/json.hpp>

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

SaturationPoint toPoint(double rho, const SaturationStats& s)
{
    // Standard error of the mean over the patch; a floor for quantisation of 8-bit values.
    return {rho, s.mean, std::max(1e-4, s.stddev / std::sqrt(double(std::max(1LL, s.pixels))))};
}

}  // namespace

CalibrationResult calibrate(const Scene& scene0, const CalibrateConfig& cfg,
                            const std::function<void(int, int)>& progress)
{
    const auto t0 = std::chrono::steady_clock::now();
    if (scene0.cameras.empty()) throw Error(scene0.source, "the scene has no camera to calibrate with");
    for (double d : cfg.densities)
        if (!(d >= 0) || !std::isfinite(d)) throw Error("--densities", "densities must be finite and >= 0");
    Scene scene = uniformSmokeScene(scene0, 0.0);
    const SurfaceSet surfaces(scene);
    CalibrationResult res;
    const int n = int(cfg.densities.size());
    for (int k = 0; k < n; ++k) {
        const double rho = cfg.densities[size_t(k)];
        scene.volumes[0].timeline = DensityTimeline::constant(rho);
        RenderConfig rc;
        rc.spp = cfg.spp;
        rc.width = cfg.width;
        rc.height = cfg.height;
        rc.seed = cfg.seed + uint64_t(k);
        rc.camera = cfg.camera;
        rc.progress = false;
        const TargetSaturation m = measureTargetSaturation(scene, surfaces, rc, cfg.target_prefix);
        res.points.push_back(toPoint(rho, m.all));
        for (const auto& [name, s] : m.patches) res.patches[name].push_back(toPoint(rho, s));
        if (progress) progress(k + 1, n);
    }
    res.fit = fitSaturationCurve(res.points, cfg.fit);
    for (const auto& [name, pts] : res.patches) {
        try {
            res.patch_fits[name] = fitSaturationCurve(pts, cfg.fit);
        } catch (const Error&) {
            // A patch whose saturation does not vary (e.g. a grey one) has no curve of its own.
        }
    }
    const auto [rho, se] = res.fit.invert(cfg.threshold_saturation);
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
    j["parameters"] = {{"S0", f.curve.S0}, {"a", f.curve.a}, {"b", f.curve.b}, {"gamma", f.curve.gamma}};
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
}  // namespace

void writeCalibrationJson(const std::string& path, const CalibrationResult& r, const CalibrateConfig& cfg,
                          const std::string& scene_source)
{
    nlohmann::json j;
    j["model"] = "S(rho) = 1 - (1 - S0 / (1 + a*(exp(b*rho) - 1)))^gamma";
    j["model_doc"] = "docs/calibration.md";
    j["combined"] = fitJson(r.fit, r.points);
    for (const auto& [name, f] : r.patch_fits) j["patches"][name] = fitJson(f, r.patches.at(name));
    j["threshold"] = {{"saturation", cfg.threshold_saturation},
                      {"density", r.threshold_density},
                      {"density_std_error", r.threshold_density_se},
                      {"path_m", cfg.path_m},
                      {"penetration_power_density_m", r.penetration_power},
                      {"penetration_power_std_error", r.penetration_power_se},
                      {"paper_density", cfg.paper_density},
                      {"engine_unit_factor", r.engine_unit_factor},
                      {"engine_unit_factor_meaning", "smokescan density units per unit of the paper's engine density"}};
    j["render"] = {{"scene", scene_source},
                   {"spp", cfg.spp},
                   {"width", cfg.width},
                   {"height", cfg.height},
                   {"seed", cfg.seed},
                   {"densities", cfg.densities},
                   {"camera", cfg.camera},
                   {"target_prefix", cfg.target_prefix},
                   {"exposure", "auto (average metering)"},
                   {"seconds", r.seconds}};
    AtomicFile f(path);
    f.stream() << j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << '\n';
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
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                r.covariance(a, b) = f.at("covariance").at(size_t(a)).at(size_t(b)).get<double>();
        for (int k = 0; k < 3; ++k) r.std_error[size_t(k)] = std::sqrt(std::max(0.0, r.covariance(k, k)));
        r.converged = f.at("converged").get<bool>();
        r.chi2 = f.value("chi2", 0.0);
        r.dof = f.value("dof", 0);
        if (!(r.curve.S0 > 0 && r.curve.S0 <= 1 && r.curve.a > 0 && r.curve.b > 0 && r.curve.gamma > 0))
            throw Error(where, "calibration parameters out of range (S0 in (0, 1], a, b, gamma > 0)");
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
