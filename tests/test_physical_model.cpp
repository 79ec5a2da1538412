// The physical return model: the behaviours of the smoke paper and its references, from physics.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <map>
#include <memory>
#include <sstream>

#include "smokescan/core/random.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/sensors/physical_model.hpp"
#include "smokescan/sensors/scanner.hpp"

using namespace smokescan;

namespace {
std::string num(double v)
{
    std::ostringstream o;
    o << std::setprecision(17) << v;
    return o.str();
}

/// A target quad 2.5 m ahead (turned by yaw_deg about z), homogeneous smoke of `density`
/// filling a 12 m box around everything, a URG-04LX and an LMS200 at the origin looking at it.
std::string roomScene(double density, const std::string& material, double yaw_deg = 0)
{
    const double c = std::cos(yaw_deg * M_PI / 180), s = std::sin(yaw_deg * M_PI / 180);
    return R"(
[[materials]]
name = "white_paper"
nir_785 = 0.8
nir_905 = 0.8
[[materials]]
name = "blue_paper"
nir_785 = 0.62
nir_905 = 0.66
[[materials]]
name = "gold_paper"
nir_785 = 0.75
nir_905 = 0.78
specular = 0.95
roughness = 0.05
[[materials]]
name = "velvet"
nir_785 = 0.03
nir_905 = 0.03
[[materials]]
name = "wall"
nir_785 = 0.6
nir_905 = 0.6
[[surfaces]]
name = "target"
material = ")" + material + R"("
type = "quad"
corner = [)" + num(2.5 + 0.5 * s) + ", " + num(-0.5 * c) + R"(, -0.5]
u = [)" + num(-s) + ", " + num(c) + R"(, 0.0]
v = [0.0, 0.0, 1.0]
[[surfaces]]
name = "room"
material = "wall"
type = "box"
position = [0, 0, 0]
size = [12, 12, 6]
[[sensors]]
name = "hokuyo"
type = "urg04lx"
model = "physical"
[[sensors]]
name = "sick"
type = "lms200"
model = "physical"
rpy_deg = [0, 0, -90]
[[smoke]]
name = "room_smoke"
type = "box"
min = [-5.9, -5.9, -2.9]
max = [5.9, 5.9, 2.9]
voxel = 0.1
density = )" + num(density) + "\n";
}

struct Rig {
    Scene scene;
    SurfaceSet surfaces;
    explicit Rig(const std::string& toml) : scene(parseScene(toml, "rig.toml", "")), surfaces(scene) {}
};

int aheadBeam(const Scanner& s)
{
    for (int i = 0; i < s.spec().n_beams; ++i)
        if (std::abs(s.beamRay(i).d.y()) < 1e-9 && s.beamRay(i).d.x() > 0) return i;
    return -1;
}
}  // namespace


struct SweepOut { double onset = NAN, max_bias_mm = 0, short_frac_after = 0; std::string causes; };

SweepOut sweep(const char* mat, double yaw, const PhysicalParams& pp, bool print = false)
{
    SweepOut o;
    int n_after = 0, n_short = 0;
    std::map<std::string, int> all;
    static std::map<std::string, std::unique_ptr<Rig>> rigs;
    auto& rp = rigs[std::string(mat) + std::to_string(yaw)];
    if (!rp) rp = std::make_unique<Rig>(roomScene(1.0, mat, yaw));
    Rig& rig = *rp;
    for (double rho = 0; rho <= 0.0101; rho += 0.0001) {
        rig.scene.volumes[0].timeline = DensityTimeline::constant(rho);
        rig.scene.sensors[0].physical = pp;
        ScanConfig c;
        c.sensor = "hokuyo";
        Scanner sc(rig.scene, rig.surfaces, c);
        const int i = aheadBeam(sc);
        const SmokeField field = SmokeField::at(rig.scene.volumes, 0.0);
        SurfaceHit hit;
        const BeamSignal sig = traceBeamSignal(sc.beamRay(i), sc.spec(), pp, rig.scene, rig.surfaces, field, &hit, nullptr);
        double sum = 0; int nok = 0, nerr = 0;
        std::map<std::string, int> causes;
        for (int k = 0; k < 200; ++k) {
            KeyedRng rng(7, k, 0);
            const BeamResult r = amcwBeam(sc.spec(), pp, sig, rng);
            causes[r.cause]++;
            if (!r.error) { sum += r.value; ++nok; if (!std::isnan(o.onset) && r.value < hit.t_m * 1000 - 100) ++n_short; }
            else ++nerr;
            if (!std::isnan(o.onset)) { ++n_after; all[r.cause]++; }
        }
        const double mean = nok ? sum / nok - hit.t_m * 1000 : 0;
        if (std::isnan(o.onset) && nerr > 100) o.onset = rho * 2.5;
        if (std::isnan(o.onset)) o.max_bias_mm = std::max(o.max_bias_mm, std::abs(mean));
        if (print) std::printf("  rho %.4f Ps %.3g Pv %.3g Pm %.3g ok %d bias %.1f\n", rho, sig.surface_power, sig.smoke_power, sig.mirror_power, nok, mean);
    }
    o.short_frac_after = n_after ? double(n_short) / n_after : 0;
    for (auto& [k, v] : all) o.causes += " " + k + "=" + std::to_string(v);
    return o;
}

/// Error onset on the bocas target's blue paper: the column c* that best separates the beams
/// that return a range (column < c*) from those that return an error code (column > c*), over a
/// run of the bocas smoke machine at 1 Hz.
double bocasBlueOnset(const PhysicalParams& pp, double t1 = 200)
{
    static const Scene scene = loadScene("bocas");
    static const SurfaceSet surfaces(scene);
    Scene sc = scene;
    sc.sensors[0].physical = pp;
    ScanConfig c;
    c.model = "physical";
    c.from_s = 0;
    c.to_s = t1;
    Scanner scanner(sc, surfaces, c);
    std::vector<std::pair<double, bool>> obs;
    const auto times = scanner.times();
    for (size_t k = 0; k < times.size(); ++k) {
        const Scan s = scanner.scanAt(times[k], k);
        for (const BeamResult& b : s.beams)
            if (b.hit.surface >= 0 && sc.surfaces[size_t(b.hit.surface)].name == "target_blue")
                obs.emplace_back(b.smoke.column_regional, b.error);
    }
    std::sort(obs.begin(), obs.end());
    // misclassified(c) = errors below c + ranges above c; scan all cut points
    long long ranges_above = 0, errors_below = 0;
    for (auto& o : obs) ranges_above += !o.second;
    long long best = ranges_above;
    double best_c = 0;
    for (size_t i = 0; i < obs.size(); ++i) {
        errors_below += obs[i].second;
        ranges_above -= !obs[i].second;
        if (errors_below + ranges_above < best) {
            best = errors_below + ranges_above;
            best_c = i + 1 < obs.size() ? 0.5 * (obs[i].first + obs[i + 1].first) : obs[i].first;
        }
    }
    return best_c;
}

TEST(PhysicalExplore, Sweep)
{
    PhysicalParams pp = physicalDefaults("urg04lx");
    double lo = 2e-5, hi = 2e-3;
    for (int it = 0; it < 16; ++it) {
        pp.noise_floor = std::sqrt(lo * hi);
        const double c = bocasBlueOnset(pp);
        std::printf("nf %.5e onset %.5f\n", pp.noise_floor, c);
        (c < 0.007 ? hi : lo) = pp.noise_floor;
    }
}
