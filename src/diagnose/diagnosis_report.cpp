#include "smokescan/diagnose/diagnosis_report.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "candidates.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/plot/format.hpp"

namespace smokescan {
namespace {

nlohmann::json num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

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

/// The covariate's bin label of observation (k, b), and a sort key.
std::pair<std::string, double> binOf(const Replay& r, const Extensions& m, const std::string& cov, size_t k, size_t b)
{
    const ReplayBeam& beam = r.beams[b];
    const ReplayScan& scan = r.scans[k];
    auto bucket = [](double v, double w, const char* f) {
        const double lo = std::floor(v / w) * w;
        return std::make_pair(fmt(f, lo, lo + w), lo);
    };
    if (cov == "surface") return {r.surface_names[size_t(beam.surface)], double(beam.surface)};
    if (cov == "incidence_deg") return bucket(beam.incidence_rad * 180 / M_PI, 15, "%.0f-%.0f");
    if (cov == "range_m") return bucket(beam.range_m, 0.5, "%.1f-%.1f");
    if (cov == "beam_angle_deg") return bucket(beam.angle_rad * 180 / M_PI, 15, "%.0f-%.0f");
    if (cov == "column") {
        const double c = detail::baseTerms<double>(r, m, {int(k), int(b)}).column;
        const double P = r.config.paper.penetration_power;
        const double x = std::min(c / P, 2.0);
        return bucket(x, 0.25, "%.2f-%.2f");  // in units of the penetration power
    }
    if (cov == "saturation") return bucket(std::isnan(scan.saturation) ? -1.0 : scan.saturation, 0.05, "%.2f-%.2f");
    if (cov == "smoke_trend") return {scan.rising ? "rising" : "falling or steady", scan.rising ? 0.0 : 1.0};
    if (cov == "time_s") return bucket(scan.time_s, 30, "%.0f-%.0f");
    throw Error("diagnose", "unknown covariate '" + cov + "'");
}

const char* const kCovariates[] = {"surface", "incidence_deg", "range_m",     "beam_angle_deg",
                                   "column",  "saturation",    "smoke_trend", "time_s"};

void figuresTable(std::ostream& o, const std::vector<ModelFigures>& before, const std::vector<ModelFigures>& after)
{
    o << "| surface | beams | log-lik/beam before | after | missed errors before | after | invented errors before | after "
         "| range RMSE before [m] | after |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (size_t i = 0; i < before.size(); ++i) {
        const auto& a = before[i];
        const ModelFigures* b = i < after.size() ? &after[i] : nullptr;
        o << "| " << (a.surface.empty() ? "all" : a.surface) << " | " << a.beams << " | "
          << fmt("%.4f | %.4f | %.3f | %.3f | %.3f | %.3f | %.4f | %.4f", a.loglik_per_beam,
                 b ? b->loglik_per_beam : NAN, a.missed_error_rate, b ? b->missed_error_rate : NAN,
                 a.invented_error_rate, b ? b->invented_error_rate : NAN, a.range_rmse_m, b ? b->range_rmse_m : NAN)
          << " |\n";
    }
}

}  // namespace

std::vector<ResidualRow> residualsBy(const Replay& r, const Extensions& m, const std::string& cov)
{
    std::map<std::pair<double, std::string>, ResidualRow> rows;
    std::map<std::pair<double, std::string>, long long> ranges;
    for (size_t k = 0; k < r.scans.size(); ++k)
        for (size_t b = 0; b < r.beams.size(); ++b) {
            if (r.beams[b].surface < 0) continue;
            const auto [label, key] = binOf(r, m, cov, k, b);
            ResidualRow& row = rows[{key, label}];
            row.bin = label;
            const auto [p_err, mu] = detail::modelPrediction(r, m, {int(k), int(b)});
            const float v = r.range_m[k][b];
            ++row.beams;
            row.predicted_error_share += p_err;
            if (std::isnan(v)) {
                row.error_share += 1;
            } else {
                long long& n = ranges[{key, label}];
                row.range_residual_m = (n == 0 ? 0.0 : row.range_residual_m) + (v - mu);
                ++n;
            }
        }
    std::vector<ResidualRow> out;
    for (auto& [key, row] : rows) {
        row.error_share /= double(row.beams);
        row.predicted_error_share /= double(row.beams);
        const long long n = ranges[key];
        if (n > 0) row.range_residual_m /= double(n);
        out.push_back(row);
    }
    return out;
}

void writeDiagnosisJson(const std::string& path, const DiagnosisResult& r, const DiagnosisSources& src)
{
    nlohmann::json j;
    j["inputs"] = {{"laser", src.laser},
                   {"saturation", src.saturation},
                   {"scene", src.scene},
                   {"calibration", src.calibration},
                   {"sensor_file", src.sensor_file},
                   {"offset_s", src.offset_s},
                   {"block_s", src.block_s}};
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
                              {"p_value", num(t.p_value)}});
    j["verdict"] = r.verdict;
    AtomicFile f(path);
    f.stream() << j.dump(2) << '\n';
    f.commit();
}

void writeDiagnosisReport(const std::string& path, const Replay& replay, const DiagnosisResult& r,
                          const DiagnosisSources& src)
{
    std::ostringstream o;
    o << "# Diagnosis of " << src.laser << "\n\n";
    o << "Scene `" << src.scene << "`, saturation `"
      << (src.saturation.empty() ? "(the scene's time line)" : src.saturation) << "`, calibration `" << src.calibration
      << "`, clock offset " << src.offset_s << " s, " << r.blocks << " blocks of " << src.block_s << " s, "
      << r.observations << " beam observations.\n\n";
    o << "**Verdict: " << r.verdict << "**\n\n";
    o << "## Findings\n\n";
    if (r.findings.empty()) o << "None: no candidate extension gained on held-out blocks at the stated level.\n\n";
    for (const auto& f : r.findings) {
        o << "- `" << f.cause << "`" << (f.target.empty() ? "" : " on " + f.target) << ": ";
        for (const auto& [name, e] : f.parameters) o << name << " = " << fmt("%.5g ± %.2g", e.value, e.se) << "; ";
        o << fmt("held-out gain %.4g nats (%.3g per beam it changes), p = %.2g over %d blocks\n", f.loglik_gain,
                 f.loglik_gain_per_beam, f.p_value, f.blocks);
    }
    o << "\n## The model before and after (the extended figures held out: each fold predicted by the other's fit)\n\n";
    figuresTable(o, r.baseline, r.extended);
    o << "\n## Candidates tried\n\n| round | cause | target | held-out gain [nats] | p |\n|---|---|---|---|---|\n";
    for (const auto& t : r.tried)
        o << "| " << t.round << " | " << t.cause << " | " << t.target << " | "
          << fmt("%.4g | %.3g", t.loglik_gain, t.p_value) << " |\n";
    o << "\n## Residuals of today's model against each covariate\n\nRecorded minus predicted: error share, and mean "
         "range where a range was recorded. The column is in units of the penetration power.\n";
    for (const char* cov : kCovariates) {
        o << "\n### " << cov
          << "\n\n| bin | beams | error share | predicted | range residual [m] |\n|---|---|---|---|---|\n";
        for (const auto& row : residualsBy(replay, Extensions{}, cov))
            o << "| " << row.bin << " | " << row.beams << " | "
              << fmt("%.3f | %.3f | %.4f", row.error_share, row.predicted_error_share, row.range_residual_m) << " |\n";
    }
    AtomicFile f(path);
    f.stream() << o.str();
    f.commit();
}

}  // namespace smokescan
