#include "smokescan/sensors/cloud_profile.hpp"

#include <algorithm>
#include <cstdio>

namespace smokescan {
namespace {

double ratio(long long a, long long b) { return b > 0 ? double(a) / double(b) : 0.0; }

bool isObstacle(const BeamResult& b, double margin_m)
{
    if (b.error) return false;
    return !b.hit.hit || b.true_range_m < b.hit.t_m - margin_m;
}

}  // namespace

double CloudProfileResult::coreObstacleShare() const { return ratio(core_obstacles, core_beams); }
double CloudProfileResult::coreErrorRate() const { return ratio(core_errors, core_beams); }
double CloudProfileResult::edgeErrorRate() const { return ratio(edge_errors, edge_beams); }
double CloudProfileResult::errorShareAtEdges() const { return ratio(edge_errors, edge_errors + core_errors); }
double CloudProfileResult::edgeShareOfBeams() const { return ratio(edge_beams, edge_beams + core_beams); }

std::string CloudProfileResult::text() const
{
    char line[512];
    std::snprintf(
        line, sizeof line,
        "clouds crossed: %lld runs of beams; in their cores (column >= %.2g x the run's peak, >= %.3g density.m) "
        "%lld beams: "
        "%.1f %% obstacles, %.1f %% error codes\n"
        "at their edges %lld beams: %.1f %% obstacles, %.1f %% error codes; %.1f %% of the clouds' error "
        "codes at the edges (%.1f %% of their beams)\n",
        runs, config.core_fraction, config.core_min_column, core_beams, 100 * coreObstacleShare(),
        100 * coreErrorRate(), edge_beams, 100 * ratio(edge_obstacles, edge_beams), 100 * edgeErrorRate(),
        100 * errorShareAtEdges(), 100 * edgeShareOfBeams());
    std::string out = line;
    if (error_causes.empty()) return out;
    out += "error causes (cores, edges):";
    for (const auto& [cause, n] : error_causes) {
        std::snprintf(line, sizeof line, " %s %lld, %lld;", cause.c_str(), n.first, n.second);
        out += line;
    }
    out.back() = '\n';
    return out;
}

void CloudProfile::add(const Scan& s)
{
    const size_t n = s.beams.size();
    size_t i = 0;
    while (i < n) {
        if (!(s.beams[i].smoke.column_local >= cfg_.min_column)) {  // also NaN
            ++i;
            continue;
        }
        size_t j = i;
        double peak = 0;
        while (j < n && s.beams[j].smoke.column_local >= cfg_.min_column)
            peak = std::max(peak, s.beams[j++].smoke.column_local);
        ++r_.runs;
        for (size_t k = i; k < j; ++k) {
            const BeamResult& b = s.beams[k];
            const bool core = b.smoke.column_local >= std::max(cfg_.core_fraction * peak, cfg_.core_min_column);
            const bool obst = isObstacle(b, cfg_.obstacle_margin_m);
            (core ? r_.core_beams : r_.edge_beams) += 1;
            (core ? r_.core_obstacles : r_.edge_obstacles) += obst;
            (core ? r_.core_errors : r_.edge_errors) += b.error;
            if (b.error) {
                auto& c = r_.error_causes[b.cause];
                (core ? c.first : c.second) += 1;
            }
        }
        i = j;
    }
}

}  // namespace smokescan
