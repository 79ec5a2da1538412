#pragma once
// A test room: one target quad 2.5 m ahead of a URG-04LX and an LMS200 (physical models) in
// homogeneous smoke. Shared by the physical-model and beam-model tests.
#include <cmath>
#include <string>

#include "scene_text.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/scene/surfaces.hpp"

namespace smokescan::test {

/// A target quad 2.5 m ahead (turned by yaw_deg about z), homogeneous smoke of `density`
/// filling a 12 m box around everything, a URG-04LX and an LMS200 at the origin looking at it.
inline std::string roomScene(double density, const std::string& material, double yaw_deg = 0)
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
name = "dark_paper"
nir_785 = 0.1
nir_905 = 0.1
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
material = ")" +
        material + R"("
type = "quad"
corner = [)" +
        tomlNumber(2.5 + 0.5 * s) + ", " + tomlNumber(-0.5 * c) + R"(, -0.5]
u = [)" +
        tomlNumber(-s) + ", " + tomlNumber(c) + R"(, 0.0]
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
density = )" +
        tomlNumber(density) + "\n";
}

struct Rig {
    Scene scene;
    SurfaceSet surfaces;
    explicit Rig(const std::string& toml) : scene(parseScene(toml, "rig.toml", "")), surfaces(scene) {}
};

}  // namespace smokescan::test
