#pragma once
// The omnicam tests' court scene (tests/test_omni_rangefinder.cpp, tests/test_omnirange_cli.cpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace smokescan::test {

/// A 4 m × 3.2 m court open to the sky: grass floor, brick-red walls 1.5 m ahead of the robot (+x),
/// 2.5 m behind, 2.0 m to its left (+y) and 1.2 m to its right (asymmetric both ways, so that a
/// turned or mirrored image would miss), lit by the sun straight above (the floor lit evenly up to
/// the walls) and the sky; an omnicam 0.931 m above the floor (400×300, R = 75 px) and a Sick
/// LMS200 at 0.3 m on a robot standing at the origin facing +x. `camera_extra` is appended to the
/// camera's table.
inline std::string omniCourt(const std::string& camera_extra = "")
{
    std::string s = R"(
[scene]
t_start_s = 0
t_end_s = 2
[[materials]]
name = "grass"
albedo = [0.10, 0.35, 0.06]
[[materials]]
name = "brick"
albedo = [0.45, 0.12, 0.08]
[[surfaces]]
name = "floor"
material = "grass"
type = "quad"
corner = [-2.5, -1.2, 0]
u = [4, 0, 0]
v = [0, 3.2, 0]
[[lights]]
name = "sky"
kind = "ambient"
radiance = 0.2
[[lights]]
name = "sun"
kind = "directional"
rpy_deg = [0, 90, 0]
irradiance = 3.0
[[robots]]
name = "r"
[[robots.keyframes]]
time_s = 0
[[sensors]]
name = "sick"
type = "lms200"
robot = "r"
position = [0, 0, 0.3]
rpy_deg = [0, 0, -90]
[[cameras]]
name = "omni"
kind = "omni"
robot = "r"
position = [0, 0, 0.931]
width = 400
height = 300
mirror_radius_px = 75
)" + camera_extra;
    const char* walls[][3] = {{"east", "[1.5, -1.2, 0]", "[0, 3.2, 0]"},
                              {"west", "[-2.5, -1.2, 0]", "[0, 3.2, 0]"},
                              {"north", "[-2.5, 2.0, 0]", "[4, 0, 0]"},
                              {"south", "[-2.5, -1.2, 0]", "[4, 0, 0]"}};
    for (const auto& w : walls)
        s += std::string("[[surfaces]]\nname = \"wall_") + w[0] +
            "\"\nmaterial = \"brick\"\ntype = \"quad\"\ncorner = " + w[1] + "\nu = " + w[2] + "\nv = [0, 0, 2]\n";
    return s;
}

/// The court's nearest wall along world bearing b [rad] from (x0, y0) [m]: walls at x = 1.5 and
/// −2.5, y = 2.0 and −1.2.
inline double courtWall(double b, double x0 = 0, double y0 = 0)
{
    const double inf = std::numeric_limits<double>::infinity();
    const double c = std::cos(b), s = std::sin(b);
    const double along_x = c > 1e-12 ? (1.5 - x0) / c : c < -1e-12 ? (-2.5 - x0) / c : inf;
    const double along_y = s > 1e-12 ? (2.0 - y0) / s : s < -1e-12 ? (-1.2 - y0) / s : inf;
    return std::min(along_x, along_y);
}

}  // namespace smokescan::test
