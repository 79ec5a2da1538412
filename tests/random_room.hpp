#pragma once
// Rooms nobody here drew: the diagnosis's tests draw them at random (docs/diagnosis.md §6) —
// corridors, labs and halls; walls of different near-infrared reflectivity (white, grey, black,
// brushed aluminium); the URG turned anywhere; one or two targets of different reflectivity in
// front of it, side by side or apart; smoke that ramps in and out slowly, comes in puffs from a
// machine, or drifts as a soft-edged cloud; scanned at 2 to 10 Hz. Each is scene text
// (docs/scene-format.md) for `parseScene`, with what the tests need to know of it.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "scene_text.hpp"
#include "smokescan/core/random.hpp"

namespace smokescan::test {

struct DrawnRoom {
    std::string text;  ///< the scene
    std::string kind;  ///< corridor, lab or hall; and the smoke's kind
    std::vector<std::string> targets;  ///< the target surfaces' names (target_*)
    double target_m = 0;  ///< the URG's distance to the target [m]
    double rate_hz = 1;  ///< the URG's scan rate
    double to_s = 0;  ///< the run's length [s]
    std::string describe() const
    {
        char buf[160];
        std::snprintf(buf, sizeof buf, "%s, target at %.2f m, %g Hz", kind.c_str(), target_m, rate_hz);
        return buf;
    }
};

/// @brief A room drawn from `seed` (the same seed, the same room).
inline DrawnRoom drawRoom(uint64_t seed)
{
    KeyedRng rng(seed, 0x200Du);
    auto uni = [&](double a, double b) { return a + (b - a) * rng.uniform(); };
    auto pick = [&](int n) { return std::min(n - 1, int(rng.uniform() * n)); };
    DrawnRoom d;
    SceneText s;
    // Materials: the NIR reflectivity is what the physical model sees (the URG-04LX at 785 nm, the
    // LMS200 at 905 nm; the same here); the paper model does not.
    s.raw(
        "[scene]\nname = \"drawn\"\nt_start_s = 0\nt_end_s = 400\n"
        "[[materials]]\nname = \"white\"\nalbedo = [0.85, 0.85, 0.85]\nnir_785 = 0.88\nnir_905 = 0.88\n"
        "[[materials]]\nname = \"grey\"\nalbedo = [0.4, 0.4, 0.4]\nnir_785 = 0.45\nnir_905 = 0.45\n"
        "[[materials]]\nname = \"black\"\nalbedo = [0.05, 0.05, 0.05]\nnir_785 = 0.06\nnir_905 = 0.06\n"
        "[[materials]]\nname = \"aluminium\"\nalbedo = [0.7, 0.7, 0.72]\nnir_785 = 0.7\nnir_905 = 0.7\n"
        "specular = 0.9\nroughness = 0.15\n"
        "[[materials]]\nname = \"paper\"\nalbedo = [0.8, 0.1, 0.1]\nnir_785 = 0.8\nnir_905 = 0.8\n"
        "[[materials]]\nname = \"dark_paper\"\nalbedo = [0.1, 0.1, 0.6]\nnir_785 = 0.2\nnir_905 = 0.2\n");
    const char* walls[] = {"white", "grey", "black", "aluminium"};
    // The room about the URG at the origin: x in [−back, length − back], y in [−side, width − side].
    double length, width;
    switch (pick(3)) {
    case 0:
        d.kind = "corridor";
        length = uni(8, 14), width = uni(1.8, 3);
        break;
    case 1:
        d.kind = "lab";
        length = uni(4, 6.5), width = uni(3.5, 6);
        break;
    default:
        d.kind = "hall";
        length = uni(10, 16), width = uni(8, 12);
        break;
    }
    const double back = uni(0.5, 0.3 * length), side = uni(0.4, width - 0.4), height = 3;
    const double x0 = -back, x1 = length - back, y0 = -side, y1 = width - side;
    // The URG's heading: along the room, across it, or anything between (its field is ±120°); the
    // target straight ahead, 1.5–4 m away and 0.3 m off the walls (a heading without that room is
    // drawn again). Nearer, the smoke that crosses the URG's threshold there would be denser than
    // the camera's calibration measures (about 0.01).
    double yaw_deg = 0, cx = 1, cy = 0, reach = 0;
    for (int tries = 0; tries < 100 && reach < 1.6; ++tries) {
        yaw_deg = pick(2) == 0 ? uni(-30, 30) : (pick(2) == 0 ? 90.0 : -90.0) + uni(-20, 20);
        cx = std::cos(yaw_deg * M_PI / 180), cy = std::sin(yaw_deg * M_PI / 180);
        reach = 4;
        if (cx > 1e-6) reach = std::min(reach, (x1 - 0.3) / cx);
        if (cx < -1e-6) reach = std::min(reach, (x0 + 0.3) / cx);
        if (cy > 1e-6) reach = std::min(reach, (y1 - 0.3) / cy);
        if (cy < -1e-6) reach = std::min(reach, (y0 + 0.3) / cy);
    }
    if (reach < 1.6) yaw_deg = 0, cx = 1, cy = 0, reach = x1 - 0.3;  // along the room: always long enough
    d.target_m = uni(1.5, std::min(4.0, reach));
    s.quad("floor", "grey", {x0, y0, 0}, {x1 - x0, 0, 0}, {0, y1 - y0, 0});
    s.quad("ceiling", "white", {x0, y0, height}, {x1 - x0, 0, 0}, {0, y1 - y0, 0});
    s.quad("wall_x0", walls[pick(4)], {x0, y0, 0}, {0, y1 - y0, 0}, {0, 0, height});
    s.quad("wall_x1", walls[pick(4)], {x1, y0, 0}, {0, y1 - y0, 0}, {0, 0, height});
    s.quad("wall_y0", walls[pick(4)], {x0, y0, 0}, {x1 - x0, 0, 0}, {0, 0, height});
    s.quad("wall_y1", walls[pick(4)], {x0, y1, 0}, {x1 - x0, 0, 0}, {0, 0, height});
    // One target or two of different reflectivity, across the beam, 0.8 m tall from z = 0.2.
    const double tx = d.target_m * cx, ty = d.target_m * cy, nx = -cy, ny = cx;  // n: across the beam
    const int n_targets = 1 + pick(2);
    const double w = uni(0.3, 0.5), gap = n_targets == 2 && pick(2) == 0 ? uni(0.1, 0.4) : 0.0;
    for (int i = 0; i < n_targets; ++i) {
        const double off = n_targets == 1 ? -0.5 * w : (i == 0 ? 0.5 * gap : -0.5 * gap - w);
        const std::string name = i == 0 ? "target_a" : "target_b";
        d.targets.push_back(name);
        s.quad(name, i == 0 ? "paper" : "dark_paper", {tx + off * nx, ty + off * ny, 0.2}, {w * nx, w * ny, 0},
               {0, 0, 0.8});
    }
    s.raw("[[sensors]]\nname = \"hokuyo\"\ntype = \"urg04lx\"\nposition = [0.0, 0.0, 0.5]\nrpy_deg = [0.0, 0.0, " +
          tomlNumber(yaw_deg) + "]\nmodel = \"paper\"\npenetration_power = 0.007\n");
    s.camera({-0.3 * cx, -0.3 * cy, 0.62}, {tx, ty, 0.6}, 320, 240, 40);
    s.ambient(1.0);
    // The smoke, in the paper's engine density: its peak passes the URG's threshold at the
    // target (P / distance) by a factor 1.5–3 (at most 0.008, within the camera's calibration),
    // so that the run holds onsets and recoveries.
    const double P = 0.007, peak = std::min(0.008, uni(1.5, 3) * P / d.target_m);
    const std::string lo = tomlVec({x0 + 0.025, y0 + 0.025, 0.025}), hi = tomlVec({x1 - 0.025, y1 - 0.025, 2.975});
    std::string timeline;
    switch (pick(3)) {
    case 0: {  // ramps in and out over 15–100 s, once or twice
        d.kind += ", slow ramps";
        const double ramp = uni(15, 100), hold = uni(10, 40), start = uni(10, 30);
        double t = start;
        timeline = "{ kind = \"keyframes\", keys = [[0, 0], [" + tomlNumber(t) + ", 0]";
        for (int i = 0; i < 2 && t + 2 * ramp + hold < 300; ++i) {
            const double level = peak * (i == 0 ? 1.0 : uni(0.6, 1.0));
            timeline += ", [" + tomlNumber(t + ramp) + ", " + tomlNumber(level) + "], [" + tomlNumber(t + ramp + hold) +
                ", " + tomlNumber(level) + "], [" + tomlNumber(t + 2 * ramp + hold) + ", 0]";
            t += 2 * ramp + hold + uni(5, 20);
        }
        d.to_s = std::min(300.0, t + 10);
        timeline += "] }";
        break;
    }
    case 1: {  // a machine's puffs: 2–3 runs of 5–30 s, dissolving over 60–150 s
        d.kind += ", puffs";
        const double tau = uni(60, 150), on = uni(5, 30);
        const double fill = peak / (tau * (1 - std::exp(-on / tau)));
        double t = uni(10, 30);
        timeline = "{ kind = \"machine\", on = [";
        const int runs = 2 + pick(2);
        for (int i = 0; i < runs; ++i) {
            timeline += (i ? ", [" : "[") + tomlNumber(t) + ", " + tomlNumber(t + on) + "]";
            t += on + uni(40, 80);
        }
        timeline += "], fill_per_s = " + tomlNumber(fill) + ", dissolve_s = " + tomlNumber(tau) + " }";
        d.to_s = std::min(300.0, t + 40);
        break;
    }
    default: {  // a soft-edged cloud over the target's half of the room, rising and falling
        d.kind += ", soft cloud";
        const double edge = uni(0.3, 0.8), rise = uni(20, 60), hold = uni(30, 80);
        std::array<double, 3> a{std::min(0.0, tx) - 1, std::min(0.0, ty) - 1, 0.025};
        std::array<double, 3> b{std::max(0.0, tx) + 1, std::max(0.0, ty) + 1, 2.975};
        a[0] = std::max(a[0], x0 + 0.025), a[1] = std::max(a[1], y0 + 0.025);
        b[0] = std::min(b[0], x1 - 0.025), b[1] = std::min(b[1], y1 - 0.025);
        timeline = "{ kind = \"keyframes\", keys = [[0, 0], [20, 0], [" + tomlNumber(20 + rise) + ", 1], [" +
            tomlNumber(20 + rise + hold) + ", 1], [" + tomlNumber(20 + 2 * rise + hold) + ", 0]] }";
        s.raw("[[smoke]]\nname = \"cloud\"\ntype = \"box\"\nrole = \"regional\"\nmin = " + tomlVec(a) + "\nmax = " +
              tomlVec(b) + "\ndensity = " + tomlNumber(peak) + "\nvoxel = 0.05\nedge_m = " + tomlNumber(edge) +
              "\nmedium = \"theatrical_fog\"\ntimeline = " + timeline + "\n");
        d.to_s = 20 + 2 * rise + hold + 20;
        timeline.clear();
        break;
    }
    }
    if (!timeline.empty())
        s.raw("[[smoke]]\nname = \"room\"\ntype = \"box\"\nrole = \"regional\"\nmin = " + lo + "\nmax = " + hi +
              "\ndensity = 1.0\nvoxel = 0.05\nmedium = \"theatrical_fog\"\ntimeline = " + timeline + "\n");
    const double rates[] = {2, 4, 5, 10};
    d.rate_hz = rates[pick(4)];
    d.text = s.str();
    return d;
}

}  // namespace smokescan::test
