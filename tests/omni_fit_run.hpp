#pragma once
// A planted omnicam run in the court (tests/omni_court.hpp) for the omnicam's fit
// (tests/test_omni_fit.cpp): the log `omnirange` would write and the camera's saturation.
#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <string>

#include "omni_court.hpp"

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
/// recovers by 270 s, sampled at 2 Hz with N(0, 0.003) noise; the omnicam's 360 scanlines (1°
/// apart, 0 ahead, counter-clockwise) read at 1 Hz from 0 to 300 s on the same clock. A scanline
/// fails with probability Φ((S* − S)/w), w = 0.015: on the east wall (S* = 0.20) it reads short
/// (0.2–0.7 of the truth), on the west wall (S* = 0.26) the maximum range 3.8 m (long); the north
/// and south walls never fail. A reading that does not fail is the truth + N(0, 0.03 m).
struct PlantedOmniRun {
    std::string log_text, saturation_text;
    std::map<std::string, double> S_star = {{"wall_east", 0.20}, {"wall_west", 0.26}};
};

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
            const double b = i * M_PI / 180, truth = courtWall(b);
            const std::string wall = courtWallName(b);
            const auto it = run.S_star.find(wall);
            const bool fails = it != run.S_star.end() && u01(rng) < 0.5 * std::erfc((S - it->second) / 0.015 / M_SQRT2);
            double r = truth + 0.03 * n01(rng);
            if (fails) r = wall == "wall_east" ? truth * (0.2 + 0.5 * u01(rng)) : 3.8;
            line += " " + std::to_string(b) + " " + std::to_string(std::llround(1000 * r));
        }
        run.log_text += line + "\n";
    }
    return run;
}

}  // namespace smokescan::test
