#include "smokescan/fit/beam_groups.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include "smokescan/core/error.hpp"
#include "smokescan/core/order_stats.hpp"
#include "smokescan/io/recorded.hpp"
#include "smokescan/io/text_input.hpp"

namespace smokescan {
namespace {

constexpr double kDeg = M_PI / 180.0;
/// A group's surface range [m]: beyond every sensor's reach (a range a sensor file then carries).
constexpr double kMaxGroupRange_m = 1000;

double number(const std::string& tok, const std::string& where)
{
    char* end = nullptr;
    const double v = std::strtod(tok.c_str(), &end);
    if (tok.empty() || *end != '\0' || !std::isfinite(v)) throw Error(where, "'" + tok + "' is not a finite number");
    return v;
}

void addInterval(BeamGroup& g, double a0_deg, double a1_deg, const std::string& where)
{
    if (!(std::abs(a0_deg) <= 360 && std::abs(a1_deg) <= 360 && a0_deg < a1_deg))
        throw Error(where, "interval of '" + g.name + "' must run from A0 to a larger A1, both within +/-360 degrees");
    g.intervals_rad.emplace_back(a0_deg * kDeg, a1_deg * kDeg);
}

}  // namespace

bool BeamGroup::contains(double a) const
{
    for (const auto& [a0, a1] : intervals_rad)
        if (a >= a0 - 1e-9 && a <= a1 + 1e-9) return true;
    return false;
}

BeamGroup parseBeamGroup(const std::string& spec, const std::string& what)
{
    const auto eq = spec.find('=');
    if (eq == std::string::npos || eq == 0)
        throw Error(what, "expects NAME=A0:A1[,A2:A3][@RANGE_M] (degrees), got '" + spec + "'");
    BeamGroup g;
    g.name = spec.substr(0, eq);
    checkColumnName(g.name, what);  // a group's name heads columns of the aligned CSV
    std::string rest = spec.substr(eq + 1);
    if (const auto at = rest.find('@'); at != std::string::npos) {
        g.range_m = number(rest.substr(at + 1), what);
        if (!(g.range_m > 0 && g.range_m <= kMaxGroupRange_m))
            throw Error(what, "range of '" + g.name + "' must be in (0, 1000] m");
        rest = rest.substr(0, at);
    }
    std::stringstream ss(rest);
    std::string iv;
    while (std::getline(ss, iv, ',')) {
        const auto colon = iv.find(':');
        if (colon == std::string::npos) throw Error(what, "interval '" + iv + "' of '" + g.name + "' is not A0:A1");
        addInterval(g, number(iv.substr(0, colon), what), number(iv.substr(colon + 1), what), what);
    }
    if (g.intervals_rad.empty()) throw Error(what, "'" + g.name + "' has no angle interval");
    return g;
}

std::vector<BeamGroup> readBeamGroupFile(const std::string& path)
{
    std::istringstream in(readTextInput(path, "beam groups file"));
    std::vector<BeamGroup> out;
    std::map<std::string, size_t> index;
    std::string line;
    for (int ln = 1; std::getline(in, line); ++ln) {
        const std::string where = path + ":" + std::to_string(ln);
        if (const auto h = line.find('#'); h != std::string::npos) line.resize(h);
        std::istringstream ss(line);
        std::vector<std::string> f;
        for (std::string t; ss >> t;) f.push_back(t);
        if (f.empty()) continue;
        if (f.size() != 3 && f.size() != 4)
            throw Error(where, "expected NAME A0_DEG A1_DEG [RANGE_M], got " + std::to_string(f.size()) + " fields");
        checkColumnName(f[0], where);  // a group's name heads columns of the aligned CSV
        auto [it, added] = index.emplace(f[0], out.size());
        if (added) out.push_back(BeamGroup{f[0], {}, 0, ""});
        BeamGroup& g = out[it->second];
        addInterval(g, number(f[1], where), number(f[2], where), where);
        if (f.size() == 4) {
            g.range_m = number(f[3], where);
            if (!(g.range_m > 0 && g.range_m <= kMaxGroupRange_m)) throw Error(where, "range must be in (0, 1000] m");
        }
    }
    if (out.empty()) throw Error(path, "names no beam groups");
    return out;
}

std::vector<BeamGroup> beamGroupsFromScene(const Scene& scene, const SurfaceSet& surfaces, const SensorMount& mount,
                                           const LrfSpec& spec, const std::string& prefix, int edge_beams)
{
    const int n = spec.n_beams;
    std::vector<int> surf(size_t(n), -1);
    std::vector<double> range(size_t(n), 0);
    for (int i = 0; i < n; ++i) {
        const double a = spec.angle(i);
        const Ray ray = mount.beamRay(a);
        const SurfaceHit h = surfaces.closest(ray, spec.range_max_m);
        if (h.hit && h.t_m >= spec.range_min_m) {
            surf[size_t(i)] = h.surface;
            range[size_t(i)] = h.t_m;
        }
    }
    std::vector<BeamGroup> out;
    std::map<int, size_t> index;
    std::map<int, std::vector<double>> ranges;
    for (int i = 0; i < n; ++i) {
        const int s = surf[size_t(i)];
        if (s < 0 || scene.surfaces[size_t(s)].name.rfind(prefix, 0) != 0) continue;
        bool interior = true;
        for (int d = -edge_beams; d <= edge_beams; ++d)
            interior = interior && i + d >= 0 && i + d < n && surf[size_t(i + d)] == s;
        if (!interior) continue;
        auto [it, added] = index.emplace(s, out.size());
        if (added) {
            const Surface& sf = scene.surfaces[size_t(s)];
            out.push_back(BeamGroup{sf.name, {}, 0, scene.materials[size_t(sf.material)].name});
        }
        BeamGroup& g = out[it->second];
        const double a = spec.angle(i), h = 0.5 * std::abs(spec.dangle_rad);
        // Extend the last interval when this beam continues it, else open a new one.
        if (!g.intervals_rad.empty() && std::abs(g.intervals_rad.back().second - (a - h)) < 1e-9)
            g.intervals_rad.back().second = a + h;
        else
            g.intervals_rad.emplace_back(a - h, a + h);
        ranges[s].push_back(range[size_t(i)]);
    }
    for (auto& [s, r] : ranges) out[index[s]].range_m = median(std::move(r));
    return out;
}

}  // namespace smokescan
