// A 3D lidar's diagnosis as JSON and Markdown (diagnose/lidar_diagnosis.hpp).
#include <cmath>
#include <nlohmann/json.hpp>

#include "report_json.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/diagnose/lidar_diagnosis.hpp"

namespace smokescan {
namespace {

using detail::num;

/// Rounding's residue (a rotation's 3e-15 deg) as 0.
double tidy(double v) { return std::abs(v) < 1e-9 ? 0.0 : v; }

/// a / b as a table cell, "-" where b is 0.
std::string shareCell(long long a, long long b) { return b > 0 ? fmt("%.4f", double(a) / double(b)) : "-"; }

nlohmann::json groupJson(const LidarGroupStats& g)
{
    return {{"clear", g.clear},
            {"missed", g.missed},
            {"missed_share", g.clear > 0 ? num(double(g.missed) / double(g.clear)) : nullptr},
            {"matched", g.matched},
            {"median_residual_m", g.matched > 0 ? num(g.median_residual_m) : nullptr}};
}

std::string surfaceName(const LidarDiagnosis& d, int s)
{
    return s >= 0 && size_t(s) < d.surface_names.size() ? d.surface_names[size_t(s)] : "surface " + std::to_string(s);
}

}  // namespace

std::string lidarFindingTarget(const LidarDiagnosis& d, const LidarFinding& f)
{
    switch (f.cause) {
    case LidarCause::WindowSector:
        return f.from_deg == f.to_deg ? std::string("-") : fmt("azimuth %.1f..%.1f deg", f.from_deg, f.to_deg);
    case LidarCause::SurfaceThreshold:
        return f.surface >= 0 ? surfaceName(d, f.surface) : std::string("-");
    case LidarCause::SmokeFirstReturns:
        return "every beam in smoke";
    default:
        return f.ring >= 0 ? fmt("ring %d", f.ring) : std::string("-");
    }
}

namespace {

const char* effectUnit(const LidarFinding& f) { return f.cause == LidarCause::BiasedChannel ? "m" : "share"; }

}  // namespace

std::string lidarDiagnosisJson(const LidarDiagnosis& d)
{
    nlohmann::json j;
    j["verdict"] = d.verdict;
    j["extended_preset"] = d.extended_preset;
    j["sensor"] = d.sensor;
    j["returns"] = d.returns;
    // Names as the user gave them; bytes JSON cannot hold (not UTF-8) and controls as \xNN.
    j["scene"] = printableWhole(d.scene);
    j["points"] = printableWhole(d.points);
    j["topic"] = d.topic.empty() ? nlohmann::json() : nlohmann::json(printableWhole(d.topic));
    j["frames"] = d.frames;
    j["empty_frames_left_out"] = d.empty_frames;
    j["beams"] = d.beams;
    j["clear_beams"] = d.clear;
    j["unmatched_points"] = d.unmatched_points;
    j["range_sd_m"] = num(d.range_sd_m);
    j["sector_deg"] = d.sector_deg;
    j["pose_mismatch_m"] = num(tidy(d.pose_mismatch_m));
    j["pose_mismatch_deg"] = num(tidy(d.pose_mismatch_deg));
    nlohmann::json tried = nlohmann::json::array();
    for (const LidarFinding& f : d.tried) {
        nlohmann::json t = {{"cause", lidarCauseName(f.cause)},
                            {"tested", f.tested},
                            {"named", f.named},
                            {"effect", num(f.effect)},
                            {"effect_se", num(f.effect_se)},
                            {"effect_unit", effectUnit(f)},
                            {"floor", num(f.floor)},
                            {"held_out_gain_nats", num(f.gain_nats)},
                            {"p", f.tested ? num(f.p_value) : nullptr}};
        if (f.cause == LidarCause::DroppingChannel || f.cause == LidarCause::WindowSector)
            t["base_rate"] = num(f.base_rate);  // the other clear beams' missed share
        if (f.cause == LidarCause::WindowSector) {
            const bool none = f.from_deg == f.to_deg;
            t["from_deg"] = none ? nlohmann::json(nullptr) : num(f.from_deg);
            t["to_deg"] = none ? nlohmann::json(nullptr) : num(f.to_deg);
        } else if (f.cause == LidarCause::SurfaceThreshold) {
            t["surface"] = f.surface >= 0 ? nlohmann::json(surfaceName(d, f.surface)) : nlohmann::json(nullptr);
        } else if (f.cause != LidarCause::SmokeFirstReturns) {
            t["ring"] = f.ring >= 0 ? nlohmann::json(f.ring) : nlohmann::json(nullptr);
        }
        tried.push_back(t);
    }
    j["tried"] = tried;
    nlohmann::json rings = nlohmann::json::array(), sectors = nlohmann::json::array();
    for (size_t c = 0; c < d.rings.size(); ++c) {
        nlohmann::json g = groupJson(d.rings[c]);
        g["ring"] = c;
        rings.push_back(g);
    }
    for (size_t b = 0; b < d.sectors.size(); ++b) {
        nlohmann::json g = groupJson(d.sectors[b]);
        g.erase("median_residual_m");
        g["from_deg"] = -180 + double(b) * d.sector_deg;
        g["to_deg"] = -180 + double(b + 1) * d.sector_deg;
        sectors.push_back(g);
    }
    j["rings"] = rings;
    j["sectors"] = sectors;
    nlohmann::json surfaces = nlohmann::json::array();
    for (const auto& [sf, o] : d.surfaces)
        surfaces.push_back({{"surface", surfaceName(d, sf)},
                            {"beams", o.beams},
                            {"returned", o.observed},
                            {"chance_sum", num(o.expected)},
                            {"sd", num(std::sqrt(o.variance))}});
    j["surfaces_in_smoke"] = surfaces;
    return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

std::string lidarDiagnosisMarkdown(const LidarDiagnosis& d, const std::string& sensor)
{
    std::string s = "# Diagnosis of a " + sensor + "'s frames\n\nVerdict: **" + d.verdict + "**\n\n";
    // Names as given, controls and bytes that are not UTF-8 as \xNN: one line whatever they hold.
    s += "Scene " + printableWhole(d.scene) + ", " + d.returns + " returns; frames read from " +
        printableWhole(d.points) + (d.topic.empty() ? std::string() : " (topic " + printableWhole(d.topic) + ")") +
        ".\n\n";
    s +=
        fmt("%zu frames, %lld beams, %lld of them clear (the replay's certain surface echoes); %lld recorded points "
            "matched no beam. Clear beams' range residual sd (robust): %.4f m.\n\n",
            d.frames, d.beams, d.clear, d.unmatched_points, d.range_sd_m);
    if (d.empty_frames > 0)
        s +=
            fmt("%zu more frame%s left out as empty: no point, or points for under a tenth of the beams the "
                "replay is sure of (a recorder's dropped or cut frames).\n\n",
                d.empty_frames, d.empty_frames == 1 ? " was" : "s were");
    if (std::isnan(d.pose_mismatch_m))
        s += "The frames carry no recorded pose (a bag's PointCloud2 frames): the scene's poses were taken.\n\n";
    else
        s += fmt("The frames' recorded start poses differ from the scene's by %.3g m and %.3g deg at most.\n\n",
                 tidy(d.pose_mismatch_m), tidy(d.pose_mismatch_deg));
    s += "Each cause's candidate was searched on the even frames and tested on the odd ones.\n\n";
    s += "| cause | target | effect | se | floor | held-out gain [nats] | p | named |\n";
    s += "|---|---|---|---|---|---|---|---|\n";
    for (const LidarFinding& f : d.tried)
        s += fmt("| %s | %s | %.4g %s | %.2g | %.3g | %.4g | %s | %s |\n", lidarCauseName(f.cause),
                 lidarFindingTarget(d, f).c_str(), f.effect, effectUnit(f), f.effect_se, f.floor, f.gain_nats,
                 f.tested ? fmt("%.2g", f.p_value).c_str() : "-", f.named ? "yes" : "no");
    s += "\n## Channels\n\n| ring | clear | missed share | median residual [m] |\n|---|---|---|---|\n";
    for (size_t c = 0; c < d.rings.size(); ++c) {
        const LidarGroupStats& g = d.rings[c];
        s += fmt("| %zu | %lld | %s | %s |\n", c, g.clear, shareCell(g.missed, g.clear).c_str(),
                 g.matched ? fmt("%.4f", g.median_residual_m).c_str() : "-");
    }
    s += "\n## Surfaces in smoke (beams that are not clear)\n\n| surface | beams | returned | chance | sd |\n"
         "|---|---|---|---|---|\n";
    for (const auto& [sf, o] : d.surfaces)
        s += fmt("| %s | %lld | %.0f | %.1f | %.1f |\n", surfaceName(d, sf).c_str(), o.beams, o.observed, o.expected,
                 std::sqrt(o.variance));
    s += "\n## Azimuth sectors (sensor frame)\n\n| from [deg] | to [deg] | clear | missed share |\n|---|---|---|---|\n";
    for (size_t b = 0; b < d.sectors.size(); ++b) {
        const LidarGroupStats& g = d.sectors[b];
        s += fmt("| %.1f | %.1f | %lld | %s |\n", -180 + double(b) * d.sector_deg, -180 + double(b + 1) * d.sector_deg,
                 g.clear, shareCell(g.missed, g.clear).c_str());
    }
    return s;
}

}  // namespace smokescan
