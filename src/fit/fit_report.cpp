// The fit's report (JSON), aligned streams (CSV) and plots (the smoke paper's Fig. 5 and 9).
#include "smokescan/fit/fit_report.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <iomanip>

#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/plot/canvas.hpp"
#include "smokescan/plot/frame.hpp"
#include "smokescan/plot/palette.hpp"
#include "threshold_fit.hpp"

namespace smokescan {
namespace {

nlohmann::json est(const Estimate& e)
{
    if (std::isnan(e.value)) return nullptr;
    return {{"value", e.value}, {"std_error", std::isnan(e.se) ? nlohmann::json(nullptr) : nlohmann::json(e.se)}};
}

}  // namespace

std::string fitReportJson(const SensorFitResult& r, const SensorFitConfig& cfg, const FitSources& src,
                          const UrgNoiseFloorResult* physical)
{
    nlohmann::json j;
    j["model"] = {{"threshold",
                   "P(error | S) = F((S* - S) / sqrt(w^2 + sigma_S^2)), F = " + std::string(errorLinkName(cfg.link))},
                  {"penetration_power", "P = rho(S*) * range_m through the calibration curve; tau = sigma_t * P"},
                  {"range", "bias(x) = bias0 + bias_slope*x, noise(x) = noise0 + noise_slope*x, x = S_ref - S [m]"},
                  {"offset", "camera time - laser time [s]"},
                  {"doc", "docs/fitting.md"}};
    j["sources"] = {{"laser", printableWhole(src.laser)},
                    {"saturation", printableWhole(src.saturation)},
                    {"calibration", printableWhole(src.calibration)},
                    {"groups_from", printableWhole(src.groups_from)},
                    {"unit_m", src.unit_m},
                    {"skipped_lines", src.skipped.size()}};
    nlohmann::json sk = nlohmann::json::array();
    for (const auto& s : src.skipped) sk.push_back(printableWhole(s.where + ": " + s.problem));
    j["sources"]["skipped"] = sk;
    j["offset"] = {{"estimated", r.offset.estimated},
                   {"offset_s", est(r.offset.offset_s)},
                   {"transitions", r.offset.transitions},
                   {"diagnosis", r.offset.diagnosis},
                   {"bootstrap_fits", r.offset.bootstrap_fits}};
    j["saturation_noise"] = r.saturation_noise;
    j["smoothing_samples"] = r.smoothing_samples;
    j["bootstrap_replicates"] = r.bootstrap_replicates;  // drawn; each estimate's bootstrap_fits: how many fitted
    j["error_method"] = r.error_method;
    j["reference_group"] = r.ok() ? nlohmann::json(r.thresholds[size_t(r.reference)].group) : nlohmann::json(nullptr);
    j["diagnoses"] = r.diagnoses;
    nlohmann::json gs = nlohmann::json::array();
    for (size_t g = 0; g < r.thresholds.size(); ++g) {
        const auto& t = r.thresholds[g];
        const auto& q = r.ranges[g];
        nlohmann::json iv = nlohmann::json::array();
        for (const auto& [a0, a1] : r.groups[g].intervals_rad) iv.push_back({a0, a1});
        nlohmann::json bins = nlohmann::json::array();
        for (const auto& b : q.bins)
            bins.push_back({{"saturation", b.S},
                            {"n", b.n},
                            {"bias_m", b.mean_m},
                            {"bias_se_m", b.se_mean_m},
                            {"noise_m", b.sd_m},
                            {"noise_se_m", b.se_sd_m}});
        gs.push_back({{"name", t.group},
                      {"material", r.groups[g].material},
                      {"angles_rad", iv},
                      {"beams", t.beams},
                      {"scans", t.scans},
                      {"errors", t.errors},
                      {"observations", t.observations},
                      {"threshold",
                       {{"fitted", t.fitted},
                        {"sharp", t.sharp},
                        {"diagnosis", t.diagnosis},
                        {"S_star", est(t.S_star)},
                        {"width", est(t.width)},
                        {"cov_S_star_width", t.cov_S_star_width},
                        {"range_m", t.range_m},
                        {"density", est(t.density)},
                        {"penetration_power_density_m", est(t.penetration_power)},
                        {"tau", est(t.tau)},
                        {"pearson_chi2", t.pearson_chi2},
                        {"deviance", t.deviance},
                        {"dof", t.dof},
                        {"variance_inflation", t.variance_inflation},
                        {"bootstrap_fits", t.bootstrap_fits}}},
                      {"range",
                       {{"fitted", q.fitted},
                        {"diagnosis", q.diagnosis},
                        {"S_ref", std::isnan(q.S_ref) ? nlohmann::json(nullptr) : nlohmann::json(q.S_ref)},
                        {"bias0_m", est(q.bias0)},
                        {"bias_slope_m", est(q.bias_slope)},
                        {"noise0_m", est(q.noise0)},
                        {"noise_slope_m", est(q.noise_slope)},
                        {"chi2_bias", q.chi2_bias},
                        {"chi2_noise", q.chi2_noise},
                        {"dof", q.dof},
                        {"observations", q.observations},
                        {"bins", bins}}}});
    }
    j["groups"] = gs;
    if (physical)
        j["physical"] = {
            {"model",
             "URG-04LX noise floor by maximum likelihood on the group's error counts, the physical model's own "
             "error probability at each scan's density (docs/fitting.md)"},
            {"ok", physical->ok},
            {"diagnosis", physical->diagnosis},
            {"group", physical->group},
            {"beams", physical->beams},
            {"scans", physical->scans},
            {"scene_time_s", physical->scene_time_s},
            {"noise_floor", est(physical->noise_floor)},
            {"se_statistical", physical->se_statistical},
            {"se_calibration", physical->se_calibration},
            {"variance_inflation", physical->variance_inflation},
            {"onset_column_density_m", est(physical->onset_column)},
            {"pearson_chi2", physical->pearson_chi2},
            {"dof", physical->dof}};
    j["config"] = {{"link", errorLinkName(cfg.link)},
                   {"estimate_offset", cfg.estimate_offset},
                   {"offset_s", cfg.offset_s},
                   {"offset_window_s", cfg.offset_window_s},
                   {"smooth_s", cfg.smooth_s},
                   {"clear_quantile", cfg.clear_quantile},
                   {"sigma_t_per_density", cfg.sigma_t_per_density}};
    return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
}

void writeFitReportJson(const std::string& path, const SensorFitResult& r, const SensorFitConfig& cfg,
                        const FitSources& src, const UrgNoiseFloorResult* physical)
{
    AtomicFile f(path);
    f.stream() << fitReportJson(r, cfg, src, physical) << '\n';
    f.commit();
}

void writeAlignedCsv(const std::string& path, const SensorFitResult& r)
{
    AtomicFile f(path);
    std::ostream& o = f.stream();
    o << "time_s,saturation";
    for (const auto& g : r.groups) o << ',' << g.name << "_errors," << g.name << "_beams," << g.name << "_mean_range_m";
    o << '\n' << std::setprecision(9);
    for (const auto& a : r.aligned) {
        o << shortest(a.time_s) << ',';
        if (!std::isnan(a.saturation)) o << a.saturation;
        for (size_t g = 0; g < a.errors.size(); ++g) {
            o << ',' << a.errors[g] << ',' << a.beams[g] << ',';
            if (!std::isnan(a.mean_range_m[g])) o << a.mean_range_m[g];
        }
        o << '\n';
    }
    f.commit();
}

void writeFitTimePlot(const std::string& path, const SensorFitResult& r, int group)
{
    const int W = 900, H = 620;
    Canvas c(W, H);
    if (r.aligned.empty()) throw Error(path, "nothing to plot");
    const double t0 = r.aligned.front().time_s, t1 = std::max(t0 + 1e-6, r.aligned.back().time_s);
    const size_t g = size_t(std::max(0, group));
    double rmax = 0;
    for (const auto& a : r.aligned)
        if (g < a.mean_range_m.size() && !std::isnan(a.mean_range_m[g])) rmax = std::max(rmax, a.mean_range_m[g]);
    const Frame top{80, 60, W - 30, 300, t0, t1, 0, 1},
        bot{80, 370, W - 30, H - 70, t0, t1, 0, std::max(0.5, rmax * 1.15)};
    const std::string name = g < r.groups.size() ? r.groups[g].name : "";
    c.text(W / 2 - 220, 28, "saturation and range over time (smoke paper, Fig. 5): " + name, 15);
    top.axes(c, "", "target saturation (camera, shifted by the fitted offset)", "%.0f", "%.1f");
    bot.axes(c, "time [s] (laser clock)", "mean range [m]; red: error codes", "%.0f", "%.1f");
    if (g < r.thresholds.size() && r.thresholds[g].fitted) {
        const int ys = top.Y(r.thresholds[g].S_star.value);
        for (int x = top.x0; x < top.x1; x += 10) c.line(x, ys, std::min(top.x1, x + 5), ys, {0.8f, 0.1f, 0.1f});
        c.text(top.x1 - 120, ys - 6, "S* = " + fmt("%.3f", r.thresholds[g].S_star.value), 12, {0.8f, 0.1f, 0.1f});
    }
    int px = -1, py = -1;
    for (const auto& a : r.aligned) {
        if (std::isnan(a.saturation)) continue;
        const int x = top.X(a.time_s), y = top.Y(a.saturation);
        if (px >= 0) c.line(px, py, x, y, {0.1f, 0.2f, 0.7f});
        px = x;
        py = y;
    }
    for (const auto& a : r.aligned) {
        if (g >= a.errors.size()) break;
        const int x = bot.X(a.time_s);
        if (a.errors[g] > 0) {
            const int h = int(std::lround(40.0 * a.errors[g] / std::max(1, a.beams[g])));
            c.line(x, bot.y1, x, bot.y1 - h, {0.85f, 0.1f, 0.1f});
        }
        if (!std::isnan(a.mean_range_m[g]))
            c.box(x - 1, bot.Y(a.mean_range_m[g]) - 1, x + 1, bot.Y(a.mean_range_m[g]) + 1, {0, 0, 0}, true);
    }
    writeImage(path, c.image());
}

void writeFitSaturationPlot(const std::string& path, const SensorFitResult& r, const SensorFitConfig& cfg)
{
    const int W = 900, H = 620;
    Canvas c(W, H);
    double smin = 1, smax = 0;
    for (const auto& a : r.aligned)
        if (!std::isnan(a.saturation)) {
            smin = std::min(smin, a.saturation);
            smax = std::max(smax, a.saturation);
        }
    if (smax <= smin) smax = smin + 0.1;
    double bmin = 0, bmax = 0;
    for (const auto& q : r.ranges)
        for (const auto& b : q.bins) {
            bmin = std::min(bmin, b.mean_m - 2 * b.sd_m);
            bmax = std::max(bmax, b.mean_m + 2 * b.sd_m);
        }
    if (bmax <= bmin) bmax = bmin + 0.05;
    const Frame top{80, 60, W - 30, 300, smin, smax, 0, 1}, bot{80, 370, W - 30, H - 70, smin, smax, bmin, bmax};
    c.text(W / 2 - 250, 28, "error rate and range against saturation (smoke paper, Fig. 9)", 15);
    top.axes(c, "", "error rate per scan; fitted threshold curves", "%.2f", "%.1f");
    bot.axes(c, "target saturation", "range - clear-air range [m] (bins: mean +/- sd)", "%.2f", "%.2f");
    for (size_t g = 0; g < r.thresholds.size(); ++g) {
        const Col col = colourOf(r.groups[g].name, g);
        for (const auto& a : r.aligned)
            if (!std::isnan(a.saturation) && a.beams[g] > 0)
                c.box(top.X(a.saturation) - 1, top.Y(double(a.errors[g]) / a.beams[g]) - 1, top.X(a.saturation) + 1,
                      top.Y(double(a.errors[g]) / a.beams[g]) + 1, col, true);
        const auto& t = r.thresholds[g];
        if (t.fitted) {
            const double w = std::hypot(std::isnan(t.width.value) ? 0.0 : t.width.value,
                                        r.saturation_noise / std::sqrt(double(r.smoothing_samples)));
            int px = -1, py = -1;
            for (int x = top.x0; x <= top.x1; ++x) {
                const double S = smin + (smax - smin) * (x - top.x0) / (top.x1 - top.x0);
                const double p = w > 0 ? detail::errorProbability(S, t.S_star.value, w, cfg.link == ErrorLink::Logistic)
                                       : double(S < t.S_star.value);
                const int y = top.Y(p);
                if (px >= 0) c.line(px, py, x, y, col);
                px = x;
                py = y;
            }
            const int xs = top.X(t.S_star.value);
            c.line(xs, top.y0, xs, top.y1, col);
        }
        c.text(top.x1 - 260, top.y0 + 16 + 16 * int(g),
               t.group +
                   (t.fitted ? "  S* = " + fmt("%.4f", t.S_star.value) + " +/- " + fmt("%.4f", t.S_star.se)
                             : "  (not fitted)"),
               12, col);
        const auto& q = r.ranges[g];
        for (const auto& b : q.bins) {
            const int x = bot.X(b.S) + int(g) * 3;
            c.line(x, bot.Y(b.mean_m - b.sd_m), x, bot.Y(b.mean_m + b.sd_m), col);
            c.box(x - 3, bot.Y(b.mean_m) - 3, x + 3, bot.Y(b.mean_m) + 3, col, true);
        }
        if (q.fitted)
            c.line(bot.X(smin), bot.Y(q.bias0.value + q.bias_slope.value * (q.S_ref - smin)), bot.X(smax),
                   bot.Y(q.bias0.value + q.bias_slope.value * (q.S_ref - smax)), col);
    }
    writeImage(path, c.image());
}

std::string plumeFitJson(const PlumeFitResult& r, const PlumeFitConfig& cfg, const std::string& laser,
                         const std::string& scene)
{
    nlohmann::json j;
    j["model"] = {{"depth", "ln d = ln D - k ln(rho / rho_ref), d = range - plume entry [m]"},
                  {"share", "P(smoke echo | rho) = 1 / (1 + exp(-s (ln rho - ln rho_50)))"},
                  {"doc", "docs/fitting.md"}};
    j["sources"] = {
        {"laser", printableWhole(laser)}, {"scene", printableWhole(scene)}, {"time_offset_s", cfg.time_offset_s}};
    j["ok"] = r.ok;
    j["diagnoses"] = r.diagnoses;
    j["observations"] = r.obs.size();
    j["rho_ref"] = std::isfinite(r.rho_ref) ? nlohmann::json(r.rho_ref) : nlohmann::json(nullptr);
    j["depth"] = {{"D_m", est(r.depth_m)},
                  {"k", est(r.exponent)},
                  {"cov_lnD_k", r.cov_lnD_k},
                  {"chi2", r.depth_chi2},
                  {"dof", r.depth_dof}};
    j["echo_share"] = {
        {"rho_50", est(r.rho_50)}, {"slope", est(r.slope)}, {"chi2", r.share_chi2}, {"dof", r.share_dof}};
    nlohmann::json bins = nlohmann::json::array();
    for (const auto& b : r.bins)
        bins.push_back(
            {{"rho_lo", b.rho_lo},
             {"rho_hi", b.rho_hi},
             {"n", b.n},
             {"smoke_echo", b.echo},
             {"surface", b.surface},
             {"error", b.error},
             {"mean_depth_m", std::isfinite(b.mean_depth_m) ? nlohmann::json(b.mean_depth_m) : nlohmann::json(nullptr)},
             {"se_depth_m", std::isfinite(b.se_depth_m) ? nlohmann::json(b.se_depth_m) : nlohmann::json(nullptr)}});
    j["bins"] = bins;
    return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
}

void writePlumeFitJson(const std::string& path, const PlumeFitResult& r, const PlumeFitConfig& cfg,
                       const std::string& laser, const std::string& scene)
{
    AtomicFile f(path);
    f.stream() << plumeFitJson(r, cfg, laser, scene) << '\n';
    f.commit();
}

std::string fitSummaryText(const SensorFitResult& r, size_t skipped)
{
    std::string out;
    if (skipped > 0) out += fmt("skipped %zu bad lines (--lenient; listed in the report)\n", skipped);
    const auto& o = r.offset;
    out += fmt("clock offset (camera - laser): %.2f +/- %.2f s%s; %d transitions; saturation noise %.4f\n",
               o.offset_s.value, o.offset_s.se, o.estimated ? "" : " (held)", o.transitions, r.saturation_noise);
    if (!r.error_method.empty())
        out += std::string(o.estimated ? "errors on S* and the offset: " : "errors on S* (the offset held): ") +
            r.error_method + "\n";
    for (size_t g = 0; g < r.thresholds.size(); ++g) {
        const auto& t = r.thresholds[g];
        const auto& q = r.ranges[g];
        if (t.fitted)
            out += fmt(
                "%-16s %3d beams  S* = %.4f +/- %.4f  w = %.4f  P = %.5f +/- %.5f density.m over %.2f m  tau = %.2f +/- %.2f\n",
                t.group.c_str(), t.beams, t.S_star.value, t.S_star.se, t.width.value, t.penetration_power.value,
                t.penetration_power.se, t.range_m, t.tau.value, t.tau.se);
        else
            out += fmt("%-16s %3d beams  not fitted\n", t.group.c_str(), t.beams);
        if (q.fitted)
            out += fmt("%-16s range bias %.4f + %.4f*(S_ref-S) m (+/- %.4f), noise %.4f + %.4f*(S_ref-S) m\n", "",
                       q.bias0.value, q.bias_slope.value, q.bias_slope.se, q.noise0.value, q.noise_slope.value);
        if (!t.diagnosis.empty()) out += "                 note: " + t.diagnosis + "\n";
    }
    for (const auto& d : r.diagnoses) out += "diagnosis: " + d + "\n";
    return out;
}

}  // namespace smokescan
