#pragma once
// A planted omnicam run in the court (tests/omni_court.hpp) for the omnicam's fit
// (tests/test_omni_fit.cpp): the log `omnirange` would write and the camera's saturation.
#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "omni_court.hpp"
#include "smokescan/omni/range_tally.hpp"
#include "smokescan/render/omni_camera.hpp"

namespace smokescan::test {

/// Which court wall is nearest along world bearing b [rad] from the origin.
inline std::string courtWallName(double b)
{
    const double c = std::cos(b), s = std::sin(b);
    const double along_x = c > 1e-12 ? 1.5 / c : c < -1e-12 ? -2.5 / c : 1e300;
    const double along_y = s > 1e-12 ? 2.0 / s : s < -1e-12 ? -1.2 / s : 1e300;
    if (along_x < along_y) return c > 0 ? "wall_east" : "wall_west";
    return s > 0 ? "wall_north" : "wall_south";
}

/// The planted run: the saturation falls from 0.35 to 0.05 (t = 30–120 s), holds to 180 s and
/// recovers by 270 s, sampled at 2 Hz with N(0, 0.003) noise; the omnicam's 360 scanlines
/// (omniBearing) read at 1 Hz from 0 to 300 s on the same clock. A scanline
/// fails with probability Φ((S* − S)/w), w = 0.015: on the east wall (S* = 0.20) it reads short
/// (0.2–0.7 of the truth), on the west wall (S* = 0.26) the maximum range 3.8 m (long); the north
/// and south walls never fail. A reading that does not fail is the truth + N(0, 0.03 m).
struct PlantedOmniRun {
    std::string log_text, saturation_text;
    std::map<std::string, double> S_star = {{"wall_east", 0.20}, {"wall_west", 0.26}};
    std::vector<ReadingOutcome> outcome;  ///< [scan · 360 + scanline]: what was planted
};

/// Scanline i's bearing as `omnirange` writes it: i degrees counter-clockwise from ahead, in
/// (−180°, 180°] (scanline 181 is at −179°).
inline double omniBearing(int i) { return (i <= 180 ? i : i - 360) * M_PI / 180; }

inline double plantedSaturation(double t)
{
    const double bump = t < 30 ? 0 : t < 120 ? (t - 30) / 90 : t < 180 ? 1 : t < 270 ? (270 - t) / 90 : 0;
    return 0.35 - 0.30 * bump;
}

inline PlantedOmniRun plantOmniRun(unsigned seed)
{
    PlantedOmniRun run;
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> n01;
    std::uniform_real_distribution<double> u01;
    run.saturation_text = "time_s,saturation\n";
    for (int j = 0; j <= 600; ++j) {
        const double t = 0.5 * j;
        run.saturation_text += std::to_string(t) + "," + std::to_string(plantedSaturation(t) + 0.003 * n01(rng)) + "\n";
    }
    for (int t = 0; t <= 300; ++t) {
        const double S = plantedSaturation(t);
        std::string line = std::to_string(t);
        for (int i = 0; i < 360; ++i) {
            const double b = omniBearing(i), truth = courtWall(b);
            const std::string wall = courtWallName(b);
            const auto it = run.S_star.find(wall);
            const bool fails = it != run.S_star.end() && u01(rng) < 0.5 * std::erfc((S - it->second) / 0.015 / M_SQRT2);
            double r = truth + 0.03 * n01(rng);
            if (fails) r = wall == "wall_east" ? truth * (0.2 + 0.5 * u01(rng)) : 3.8;
            run.outcome.push_back(!fails                    ? ReadingOutcome::Ok
                                      : wall == "wall_east" ? ReadingOutcome::Short
                                                            : ReadingOutcome::Long);
            line += " " + std::to_string(b) + " " + std::to_string(std::llround(1000 * r));
        }
        run.log_text += line + "\n";
    }
    return run;
}

/// The court, the robot turned by yaw_deg, with what a fit or a diagnosis reads beside the omnicam: a blue paper target on the
/// east wall (x = 1.49, 0.6 m square, 0.3 m above the floor), a camera 3.8 m from it, and a
/// regional smoke box filling the court (density 1 scaled by a machine's time line: on from 20 s
/// to 50 s at 3e-4 /s, clearing with 40 s). experiments/omnicam_fit/smoky_court.toml is the same
/// with a URG-04LX beside the Sick.
inline std::string smokyCourt(double yaw_deg = 0)
{
    std::string s = omniCourt();
    s.replace(s.find("t_end_s = 2"), 11, "t_end_s = 300");
    s.replace(s.find("time_s = 0\n"), 11, "time_s = 0\nyaw_deg = " + std::to_string(yaw_deg) + "\n");
    return s + R"(
[[materials]]
name = "blue_paper"
albedo = [0.04, 0.12, 0.55]
nir_785 = 0.62
nir_905 = 0.66
[[surfaces]]
name = "target_paper"
material = "blue_paper"
type = "quad"
corner = [1.49, -0.3, 0.3]
u = [0, 0.6, 0]
v = [0, 0, 0.6]
[[cameras]]
name = "target_camera"
position = [-2.3, 0.3, 0.6]
look_at = [1.49, 0.0, 0.6]
width = 320
height = 240
hfov_deg = 30.0
[[smoke]]
name = "court"
type = "box"
role = "regional"
min = [-2.5, -1.2, 0.0]
max = [1.5, 2.0, 2.0]
density = 1.0
voxel = 0.05
medium = "theatrical_fog"
timeline = { kind = "machine", on = [[20.0, 50.0]], fill_per_s = 0.0003, dissolve_s = 40.0 }
)";
}

/// The court's omni camera (omniCourt(): 400×300, R = 75 px) at the origin.
inline OmniCamera courtCamera()
{
    OmniIntrinsics k;
    k.width = 400;
    k.height = 300;
    k.cx = 200;
    k.cy = 150;
    k.mirror_radius = 75;
    return OmniCamera(Pose{}, k);
}

/// A planted run for the omnicam's diagnosis in smokyCourt(yaw_deg): the smoke's density rises
/// from 0 to 0.004 (t = 30–120 s), holds to 180 s and clears by 270 s; `saturation(ρ)` turns it
/// into the camera's series (2 Hz, N(0, 0.002) noise). The omnicam reads at 0.5 Hz; a clear reading
/// is the floor distance of the image pixel nearest the wall's foot (the court's camera: R = 75 px,
/// h = 0.931 m). Three planted effects, none of them in today's model:
/// - a scanline whose column along its line of sight, ρ·√(d² + h²), exceeds its wall's onset (P;
///   on the north wall P·e^−0.7), with a spread of 0.02 in ln column, reads short (0.2–0.7 of the
///   truth), never "no return";
/// - on the scanlines at world bearings 170°–190° (the west wall, across the ±180° seam of the
///   log's bearings when yaw_deg = 0) half the readings, in clear air too, read the maximum range
///   3.8 m: a smudge on the mirror, an obstacle missed.
template <class Curve>
PlantedOmniRun plantOmniDiagnosisRun(unsigned seed, double P, const Curve& saturation, double yaw_deg = 0)
{
    PlantedOmniRun run;
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> n01;
    std::uniform_real_distribution<double> u01;
    const double h = 0.931;
    const OmniCamera cam = courtCamera();
    const auto density = [](double t) {
        return 0.004 * (t < 30 ? 0 : t < 120 ? (t - 30) / 90 : t < 180 ? 1 : t < 270 ? (270 - t) / 90 : 0);
    };
    run.saturation_text = "time_s,saturation\n";
    for (int j = 0; j <= 600; ++j) {
        const double t = 0.5 * j;
        run.saturation_text +=
            std::to_string(t) + "," + std::to_string(saturation(density(t)) + 0.002 * n01(rng)) + "\n";
    }
    for (int t = 0; t <= 300; t += 2) {
        std::string line = std::to_string(t);
        for (int i = 0; i < 360; ++i) {
            const double b = omniBearing(i), world = b + yaw_deg * M_PI / 180;
            const double truth = courtWall(world), sight = std::hypot(truth, h);
            const double onset = courtWallName(world) == "wall_north" ? P * std::exp(-0.7) : P;
            const double C = density(t) * sight;
            const bool stopped = C > 0 && std::log(C) > std::log(onset) + 0.02 * n01(rng);
            const double world_deg = std::remainder(world, 2 * M_PI) * 180 / M_PI;
            const bool smudged = std::abs(world_deg) >= 170 && u01(rng) < 0.5;
            const double clear = cam.floorDistance(std::round(cam.radius(std::atan(truth / h))), h);
            const double r = smudged ? 3.8 : stopped ? truth * (0.2 + 0.5 * u01(rng)) : clear;
            run.outcome.push_back(smudged       ? ReadingOutcome::Long
                                      : stopped ? ReadingOutcome::Short
                                                : ReadingOutcome::Ok);
            line += " " + std::to_string(b) + " " + std::to_string(std::llround(1000 * r));
        }
        run.log_text += line + "\n";
    }
    return run;
}

}  // namespace smokescan::test
