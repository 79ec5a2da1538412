#include "smokescan/diagnose/diagnosis_report.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

#include "candidates.hpp"
#include "causes.hpp"
#include "report_json.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/io/image.hpp"
#include "smokescan/plot/frame.hpp"

namespace smokescan {
namespace {

using detail::num;

/// A value for a report table; "–" when there is none (not tested, not defined).
std::string orDash(double v, const char* format) { return std::isfinite(v) ? fmt(format, v) : "–"; }

nlohmann::json figuresJson(const std::vector<ModelFigures>& figs)
{
    nlohmann::json j = nlohmann::json::object();
    for (const auto& f : figs)
        j[f.surface.empty() ? "all" : f.surface] = {{"beams", f.beams},
                                                    {"loglik_per_beam", num(f.loglik_per_beam)},
                                                    {"missed_error_rate", num(f.missed_error_rate)},
                                                    {"invented_error_rate", num(f.invented_error_rate)},
                                                    {"range_rmse_m", num(f.range_rmse_m)}};
    return j;
}

/// What the residuals are binned by: parsed once from its name, switched on per observation.
enum class Covariate { Surface, IncidenceDeg, RangeM, BeamAngleDeg, Column, Saturation, SmokeTrend, TimeS };
struct CovariateName {
    Covariate covariate;
    const char* name;
};
constexpr CovariateName kCovariateNames[] = {
    {Covariate::Surface, "surface"},        {Covariate::IncidenceDeg, "incidence_deg"},
    {Covariate::RangeM, "range_m"},         {Covariate::BeamAngleDeg, "beam_angle_deg"},
    {Covariate::Column, "column"},          {Covariate::Saturation, "saturation"},
    {Covariate::SmokeTrend, "smoke_trend"}, {Covariate::TimeS, "time_s"}};

Covariate parseCovariate(const std::string& name)
{
    for (const auto& c : kCovariateNames)
        if (name == c.name) return c.covariate;
    throw Error("diagnose", "unknown covariate '" + name + "'");
}

/// The covariate's bin label of observation (k, b), and a sort key.
std::pair<std::string, double> binOf(const Replay& r, const detail::ReplayModel& m, Covariate cov, size_t k, size_t b)
{
    const ReplayBeam& beam = r.beams[b];
    const ReplayScan& scan = r.scans[k];
    auto bucket = [](double v, double w, const char* f) {
        const double lo = std::floor(v / w) * w;
        return std::make_pair(fmt(f, lo, lo + w), lo);
    };
    switch (cov) {
    case Covariate::Surface:
        return {r.surface_names[size_t(beam.surface)], double(beam.surface)};
    case Covariate::IncidenceDeg:
        return bucket(beam.incidence_rad * 180 / M_PI, 15, "%.0f-%.0f");
    case Covariate::RangeM:
        return bucket(beam.range_m, 0.5, "%.1f-%.1f");
    case Covariate::BeamAngleDeg:
        return bucket(beam.angle_rad * 180 / M_PI, 15, "%.0f-%.0f");
    case Covariate::Column: {
        const double c = detail::baseTerms<double>(r, m, {int(k), int(b)}).column;
        const double P = r.config.paper.penetration_power;
        const double x = std::min(c / P, 2.0);
        return bucket(x, 0.25, "%.2f-%.2f");  // in units of the penetration power
    }
    case Covariate::Saturation:
        return bucket(std::isnan(scan.saturation) ? -1.0 : scan.saturation, 0.05, "%.2f-%.2f");
    case Covariate::SmokeTrend:
        return {scan.rising ? "rising" : "falling or steady", scan.rising ? 0.0 : 1.0};
    case Covariate::TimeS:
        return bucket(scan.time_s, 30, "%.0f-%.0f");
    }
    return {"", 0.0};
}

using detail::Shown;

double shownValue(const ResidualRow& row, Shown s)
{
    switch (s) {
    case Shown::ErrorShare:
        return row.error_share - row.predicted_error_share;
    case Shown::RangeMean:
        return row.range_residual_m;
    case Shown::RangeSpread:
        return row.range_rms_m - row.predicted_sd_m;
    }
    return NAN;
}

const char* shownLabel(Shown s)
{
    switch (s) {
    case Shown::ErrorShare:
        return "error share: recorded - predicted";
    case Shown::RangeMean:
        return "range: mean recorded - predicted [m]";
    case Shown::RangeSpread:
        return "range: RMS residual - predicted sd [m]";
    }
    return "";
}

/// The residuals before (red) and after (blue) against the finding's covariate, bin by bin.
void writeFindingPlot(const std::string& path, const std::string& title, const std::string& covariate, Shown shown,
                      const std::vector<ResidualRow>& before, const std::vector<ResidualRow>& after)
{
    const int W = 900, H = 520;
    double lo = 0, hi = 0;
    for (const auto* rows : {&before, &after})
        for (const auto& row : *rows) {
            const double v = shownValue(row, shown);
            if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
        }
    const double pad = 0.1 * std::max(hi - lo, 1e-3);
    const Frame f{100, 60, W - 30, H - 90, -0.5, std::max(0.5, double(before.size()) - 0.5), lo - pad, hi + pad};
    Canvas c(W, H);
    c.text(f.x0, 28, title, 15);
    f.axes(c, "", shownLabel(shown), "", "%.3f");
    c.line(f.x0, f.Y(0), f.x1, f.Y(0), {0.6f, 0.6f, 0.6f});
    for (size_t i = 0; i < before.size(); ++i)
        if (i % std::max<size_t>(1, before.size() / 8) == 0) c.text(f.X(double(i)) - 20, f.y1 + 20, before[i].bin, 11);
    c.text((f.x0 + f.x1) / 2 - 90, f.y1 + 44,
           covariate == "column" ? "smoke column / penetration power (bins)" : covariate + " (bins)", 13);
    const Col red{0.8f, 0.1f, 0.1f}, blue{0.1f, 0.2f, 0.75f};
    auto series = [&](const std::vector<ResidualRow>& rows, const Col& col, int dx) {
        for (size_t i = 0; i < rows.size(); ++i) {
            const double v = shownValue(rows[i], shown);
            if (!std::isfinite(v)) continue;
            const int x = f.X(double(i)) + dx, y = f.Y(v);
            c.line(x, f.Y(0), x, y, col);
            c.box(x - 3, y - 3, x + 3, y + 3, col, true);
        }
    };
    series(before, red, -4);
    series(after, blue, 4);
    c.text(f.x1 - 260, f.y0 + 16, after.empty() ? "today's model" : "red: today's model; blue: extended", 12);
    writeImage(path, c.image());
}

const char* const kCovariates[] = {"surface", "incidence_deg", "range_m",     "beam_angle_deg",
                                   "column",  "saturation",    "smoke_trend", "time_s"};

/// A table cell: `v` in format `f`, or – where it has no value (NaN: no ranges in the bin).
std::string cell(const char* f, double v) { return std::isnan(v) ? "–" : fmt(f, v); }

void figuresTable(std::ostream& o, const std::vector<ModelFigures>& before, const std::vector<ModelFigures>& after)
{
    o << "| surface | beams | log-lik/beam before | after | missed errors before | after | invented errors before | after "
         "| range RMSE before [m] | after |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (size_t i = 0; i < before.size(); ++i) {
        const auto& a = before[i];
        const ModelFigures* b = i < after.size() ? &after[i] : nullptr;
        o << "| " << (a.surface.empty() ? "all" : a.surface) << " | " << a.beams << " | "
          << cell("%.4f", a.loglik_per_beam) << " | " << cell("%.4f", b ? b->loglik_per_beam : NAN) << " | "
          << cell("%.3f", a.missed_error_rate) << " | " << cell("%.3f", b ? b->missed_error_rate : NAN) << " | "
          << cell("%.3f", a.invented_error_rate) << " | " << cell("%.3f", b ? b->invented_error_rate : NAN) << " | "
          << cell("%.4f", a.range_rmse_m) << " | " << cell("%.4f", b ? b->range_rmse_m : NAN) << " |\n";
    }
}

/// The surface a finding targets (−1: a sector, or none).
int surfaceIndex(const Replay& r, const std::string& name)
{
    const auto it = std::find(r.surface_names.begin(), r.surface_names.end(), name);
    return it == r.surface_names.end() ? -1 : int(it - r.surface_names.begin());
}

}  // namespace

std::vector<ResidualRow> residualsBy(const Replay& r, const ModelExtensions& model, const std::string& covariate,
                                     int surface)
{
    const Covariate cov = parseCovariate(covariate);
    const detail::ReplayModel m(r, model), prior(r, r.prior);
    struct Sums {
        ResidualRow row;
        long long ranges = 0;
        double sum = 0, sum2 = 0, var = 0;
    };
    std::map<std::pair<double, std::string>, Sums> rows;
    for (size_t k = 0; k < r.scans.size(); ++k)
        for (size_t b = 0; b < r.beams.size(); ++b) {
            if (r.beams[b].surface < 0 || (surface >= 0 && r.beams[b].surface != surface)) continue;
            const auto [label, key] = binOf(r, prior, cov, k, b);  // the same bins for every model
            Sums& s = rows[{key, label}];
            s.row.bin = label;
            const detail::Prediction p = detail::modelPrediction(r, m, {int(k), int(b)});
            const float v = r.range_m[k][b];
            ++s.row.beams;
            s.row.predicted_error_share += p.p_err;
            if (std::isnan(v)) {
                s.row.error_share += 1;
            } else {
                ++s.ranges;
                s.sum += v - p.mean_m;
                s.sum2 += (v - p.mean_m) * (v - p.mean_m);
                s.var += p.sd_m * p.sd_m;
            }
        }
    std::vector<ResidualRow> out;
    for (auto& [key, s] : rows) {
        ResidualRow row = s.row;
        row.error_share /= double(row.beams);
        row.predicted_error_share /= double(row.beams);
        if (s.ranges > 0) {
            row.range_residual_m = s.sum / double(s.ranges);
            row.range_rms_m = std::sqrt(s.sum2 / double(s.ranges));
            row.predicted_sd_m = std::sqrt(s.var / double(s.ranges));
        }
        out.push_back(row);
    }
    return out;
}

std::string diagnosisJson(const DiagnosisResult& r, const DiagnosisSources& src)
{
    nlohmann::json j;
    j["inputs"] = {{"laser", printableWhole(src.laser)},
                   {"saturation", printableWhole(src.saturation)},
                   {"scene", printableWhole(src.scene)},
                   {"calibration", printableWhole(src.calibration)},
                   {"sensor_file", printableWhole(src.sensor_file)},
                   {"offset_s", src.offset_s},
                   {"block_s", src.block_s},
                   {"smoke_shape", smokeShapeName(r.shape)}};
    j["shape_error_ln"] = num(r.shape_error_ln);
    j["blocks"] = r.blocks;
    j["observations"] = r.observations;
    j["baseline"] = figuresJson(r.baseline);
    j["extended"] = figuresJson(r.extended);
    j["findings"] = nlohmann::json::array();
    for (const auto& f : r.findings) {
        nlohmann::json p = nlohmann::json::object();
        for (const auto& [name, e] : f.parameters) p[name] = {{"value", num(e.value)}, {"std_error", num(e.se)}};
        j["findings"].push_back({{"cause", f.cause},
                                 {"target", f.target},
                                 {"parameters", p},
                                 {"heldout",
                                  {{"loglik_gain_per_beam", num(f.loglik_gain_per_beam)},
                                   {"loglik_gain", num(f.loglik_gain)},
                                   {"p_value", num(f.p_value)},
                                   {"blocks", f.blocks}}}});
    }
    j["tried"] = nlohmann::json::array();
    for (const auto& t : r.tried)
        j["tried"].push_back({{"round", t.round},
                              {"cause", t.cause},
                              {"target", t.target},
                              {"loglik_gain", num(t.loglik_gain)},
                              {"p_value", num(t.p_value)},
                              {"effect", num(t.effect)},
                              {"effect_std_error", num(t.effect_se)},
                              {"blocks", num(t.blocks)},
                              {"level", num(t.level)},
                              {"floor", num(t.floor)}});
    j["verdict"] = r.verdict;
    return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
}

void writeDiagnosisJson(const std::string& path, const DiagnosisResult& r, const DiagnosisSources& src)
{
    AtomicFile f(path);
    f.stream() << diagnosisJson(r, src) << '\n';
    f.commit();
}

void writeDiagnosisReport(const std::string& path, const Replay& replay, const DiagnosisResult& r,
                          const DiagnosisSources& src)
{
    std::ostringstream o;
    o << "# Diagnosis of " << printableWhole(src.laser) << "\n\n";
    o << "Scene `" << printableWhole(src.scene) << "`, saturation `"
      << (src.saturation.empty() ? "(the scene's time line)" : printableWhole(src.saturation)) << "`, calibration `"
      << printableWhole(src.calibration) << "`, clock offset " << src.offset_s << " s, " << r.blocks
      << " blocks of at most " << src.block_s << " s, " << r.observations
      << " beam observations; the smoke's shape along the beams: " << smokeShapeName(r.shape) << ".\n\n";
    if (r.shape == SmokeShape::Reference && r.shape_error_ln >= kShapeWarningLn)
        o << fmt(
            "**The scene's smoke changes shape over its time line**: its densest state, scaled, misstates the "
            "beams' columns by %.2f in ln (rms) where they matter. Estimates read against it are attenuated "
            "and their errors too small; if the scene's time line says where the smoke was, run again "
            "with `--smoke-shape timeline`.\n\n",
            r.shape_error_ln);
    o << "**Verdict: " << r.verdict << "**\n\n";
    o << "## Findings\n\n";
    if (r.findings.empty()) o << "None: no candidate extension gained on held-out blocks at the stated level.\n\n";
    for (const auto& f : r.findings) {
        o << "- `" << f.cause << "`" << (f.target.empty() ? "" : " on " + f.target) << ": ";
        for (const auto& [name, e] : f.parameters) o << name << " = " << fmt("%.5g ± %.2g", e.value, e.se) << "; ";
        o << fmt("held-out gain %.4g nats (%.3g per beam it changes), p = %.2g over %d blocks\n", f.loglik_gain,
                 f.loglik_gain_per_beam, f.p_value, f.blocks);
    }
    for (size_t i = 0; i < r.findings.size(); ++i) {
        const Finding& fd = r.findings[i];
        const detail::CauseRow& v = *detail::causeRow(fd.cause);  // a finding's cause is one of the table's
        const int surface = fd.target.empty() ? -1 : surfaceIndex(replay, fd.target);
        const auto before = residualsBy(replay, replay.prior, v.covariate, surface);
        const auto after = residualsBy(replay, r.model, v.covariate, surface);
        const std::string png = fmt("finding_%zu.png", i + 1);
        writeFindingPlot((std::filesystem::path(path).parent_path() / png).string(),
                         fd.cause + (fd.target.empty() ? "" : " on " + fd.target) + ": residuals before and after",
                         v.covariate, v.shown, before, after);
        o << "\n### " << fd.cause << (fd.target.empty() ? "" : " on " + fd.target) << "\n\n![" << fd.cause << "]("
          << png << ")\n\n| " << v.covariate << " | beams | " << shownLabel(v.shown)
          << ", before | after |\n|---|---|---|---|\n";
        for (size_t k = 0; k < before.size() && k < after.size(); ++k)
            o << "| " << before[k].bin << " | " << before[k].beams << " | "
              << cell("%.4f", shownValue(before[k], v.shown)) << " | " << cell("%.4f", shownValue(after[k], v.shown))
              << " |\n";
    }
    o << "\n## The model before and after (the extended figures held out: each fold predicted by the other's fit)\n\n";
    figuresTable(o, r.baseline, r.extended);
    o << "\n## Candidates tried\n\nA candidate is named when p is below its family's level and its fitted effect "
         "reaches its cause's floor (docs/diagnosis.md §4); p is – where it was not tested (no held-out gain, or the "
         "effect below its floor); `blocks` is how many time blocks its gain is spread over (the test "
         "cannot pass on fewer than log2(1/level)).\n\n| round | cause | target | held-out gain [nats] | p | "
         "level | blocks | effect ± se | floor | effect measured as |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& t : r.tried) {
        const detail::CauseRow* row = detail::causeRow(t.cause);
        o << "| " << t.round << " | " << t.cause << " | " << t.target << " | " << fmt("%.4g | ", t.loglik_gain)
          << orDash(t.p_value, "%.3g") << fmt(" | %.2g | %.1f | ", t.level, t.blocks) << orDash(t.effect, "%.3g")
          << " ± " << orDash(t.effect_se, "%.2g") << fmt(" | %.3g", t.floor) << " | " << (row ? row->floor_unit : "")
          << " |\n";
    }
    o << "\n## Residuals of today's model against each covariate\n\nRecorded minus predicted: error share, and mean "
         "range where a range was recorded. The column is in units of the penetration power.\n";
    // The worst few: the covariates whose bins (of at least 50 beams) miss the error share most.
    std::vector<std::pair<double, std::string>> worst;
    std::map<std::string, std::vector<ResidualRow>> rows;
    for (const char* cov : kCovariates) {
        rows[cov] = residualsBy(replay, replay.prior, cov);
        double miss = 0;
        for (const auto& row : rows[cov])
            if (row.beams >= 50) miss = std::max(miss, std::abs(row.error_share - row.predicted_error_share));
        worst.emplace_back(-miss, cov);
    }
    std::sort(worst.begin(), worst.end());
    o << "\nThe three that miss the error share most, plotted: ";
    for (size_t i = 0; i < 3 && i < worst.size(); ++i) {
        const std::string png = fmt("worst_%zu.png", i + 1);
        writeFindingPlot((std::filesystem::path(path).parent_path() / png).string(),
                         "today's model against " + worst[i].second + ": error share residual", worst[i].second,
                         Shown::ErrorShare, rows[worst[i].second], {});
        o << (i ? ", " : "") << "[" << worst[i].second << "](" << png << ") (" << fmt("%.3f", -worst[i].first) << ")";
    }
    o << ".\n";
    for (const char* cov : kCovariates) {
        o << "\n### " << cov
          << "\n\n| bin | beams | error share | predicted | range residual [m] |\n|---|---|---|---|---|\n";
        for (const auto& row : rows[cov])
            o << "| " << row.bin << " | " << row.beams << " | " << cell("%.3f", row.error_share) << " | "
              << cell("%.3f", row.predicted_error_share) << " | " << cell("%.4f", row.range_residual_m) << " |\n";
    }
    AtomicFile f(path);
    f.stream() << o.str();
    f.commit();
}

}  // namespace smokescan
