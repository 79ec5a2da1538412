// Scenes: the built-in BOCAS room, Embree distances against geometry, OBJ meshes, strict parsing.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "smokescan/core/error.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/scene/surfaces.hpp"

#include "scratch.hpp"

using namespace smokescan;

namespace {
std::string errorOf(const std::string& toml)
{
    try {
        parseScene(toml, "s.toml", "");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

const char* kMinimal = R"(
[[materials]]
name = "white"
[[surfaces]]
name = "wall"
material = "white"
type = "box"
position = [3.0, 0.0, 0.5]
size = [0.2, 4.0, 2.0]
)";
}  // namespace

TEST(Scene, BocasHasThePapersSetUp)
{
    const Scene s = loadScene("bocas");
    EXPECT_EQ(s.findSensor("urg04lx"), 0);
    EXPECT_GE(s.findSensor("lms200"), 0);
    EXPECT_EQ(s.cameras.size(), 1u);
    EXPECT_EQ(s.lights[0].power_w, 70.0);
    int bollards = 0;
    for (const auto& f : s.surfaces) bollards += f.name.rfind("bollard", 0) == 0;
    EXPECT_EQ(bollards, 3);
    const SurfaceSet set(s);
    // The target straight ahead at 2.5 m, blue on the left, gold on the right.
    const Vec3 o = s.sensors[0].pose.t;
    auto hitName = [&](double deg) {
        const double a = deg * M_PI / 180;
        const SurfaceHit h = set.closest(Ray{o, Vec3(std::cos(a), std::sin(a), 0)}, 10);
        return h.hit ? s.surfaces[size_t(h.surface)].name : std::string("none");
    };
    const SurfaceHit h = set.closest(Ray{o, Vec3::UnitX()}, 10);
    ASSERT_TRUE(h.hit);
    EXPECT_NEAR(h.t_m, 2.5, 1e-6);
    EXPECT_NEAR(h.normal.x(), -1.0, 1e-9);
    EXPECT_EQ(hitName(0), "target_yellow");
    EXPECT_EQ(hitName(6), "target_blue");
    EXPECT_EQ(hitName(-6), "target_gold");
    EXPECT_EQ(hitName(-18), "steel_plate_1");
    EXPECT_EQ(hitName(-25), "steel_plate_2");
    // Bollards stand below the beam plane: the beam passes over them.
    EXPECT_EQ(hitName(std::atan2(0.3, 1.3) * 180 / M_PI), "wall_back");
    // The smoke machine fills the room: density rises in its runs, falls after.
    const auto& tl = s.volumes.at(0).timeline;
    EXPECT_EQ(tl.at(10), 0.0);
    EXPECT_GT(tl.at(130), 0.0028);
    EXPECT_LT(tl.at(30), 0.0028);
    EXPECT_LT(tl.at(340), 0.0028);
}

TEST(Surfaces, CylinderAndBoxDistances)
{
    const std::string toml = std::string(kMinimal) + R"(
[[surfaces]]
name = "post"
material = "white"
type = "cylinder"
position = [1.0, 1.0, 0.0]
radius = 0.1
height = 1.0
)";
    const Scene s = parseScene(toml, "t.toml", "");
    const SurfaceSet set(s);
    EXPECT_NEAR(set.closest(Ray{Vec3(0, 0, 0.5), Vec3::UnitX()}, 10).t_m, 2.9, 1e-6);
    // Towards the post's axis: distance |c| − r, within the 128-facet sagitta (r·(1 − cos(π/128))).
    const Vec3 d = Vec3(1, 1, 0).normalized();
    const SurfaceHit h = set.closest(Ray{Vec3(0, 0, 0.5), d}, 10);
    EXPECT_EQ(s.surfaces[size_t(h.surface)].name, "post");
    EXPECT_NEAR(h.t_m, std::sqrt(2.0) - 0.1, 0.1 * (1 - std::cos(M_PI / 128)) + 1e-6);
    EXPECT_FALSE(set.closest(Ray{Vec3(0, 0, 0.5), -Vec3::UnitX()}, 10).hit);
    EXPECT_FALSE(set.closest(Ray{Vec3(0, 0, 0.5), Vec3::UnitX()}, 2.0).hit);  // beyond t_max
}

TEST(Scene, ObjMeshSurfaceAndSmokeArea)
{
    namespace fs = std::filesystem;
    const fs::path dir = smokescan::test::scratch("obj");
    {
        std::ofstream o(dir / "cube.obj");
        o << "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
             "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    }
    // A cube of half-size 0.5 m at x = 3 as a surface; the same cube, half-size 1.0 m (faces on
    // the 0.1 m voxel faces once offset by 0.05), filled with smoke.
    const std::string toml = R"(
[[materials]]
name = "m"
[[surfaces]]
name = "cube"
material = "m"
type = "mesh"
file = "cube.obj"
position = [3.0, 0.0, 0.0]
scale = 0.5
[[smoke]]
name = "cloud"
type = "mesh"
file = "cube.obj"
position = [0.05, 0.05, 0.05]
density = 0.004
voxel = 0.1
)";
    const Scene s = parseScene(toml, (dir / "s.toml").string(), dir.string());
    const SurfaceSet set(s);
    EXPECT_NEAR(set.closest(Ray{Vec3(0, 0.01, 0.02), Vec3::UnitX()}, 10).t_m, 2.5, 1e-6);
    const SmokeField f = SmokeField::at(s.volumes, 0);
    const BeamSmoke b = f.trace(Ray{Vec3(-5, 0.01, 0.02), Vec3::UnitX()}, 0, 10, {});
    EXPECT_NEAR(b.column_regional, 0.004 * 2.0, 1e-9);
    fs::remove_all(dir);
}

TEST(SceneErrors, OneLineWithFileAndLine)
{
    EXPECT_EQ(errorOf(kMinimal), "");
    EXPECT_EQ(errorOf(std::string(kMinimal) + "colour = 1\n"), "s.toml:10: unknown key 'surfaces[0].colour'");
    EXPECT_EQ(errorOf(std::string("colour = 1\n") + kMinimal), "s.toml:1: unknown key 'colour'");
    EXPECT_EQ(errorOf("[[materials]]\nname = \"a\"\nalbdo = [1,1,1]\n"), "s.toml:3: unknown key 'materials[0].albdo'");
    EXPECT_EQ(errorOf("[[materials]]\nname = 3\n"), "s.toml:2: materials[0].name must be a string");
    EXPECT_EQ(errorOf("[[materials]]\nname = \"a\"\nnir_785 = \"high\"\n"),
              "s.toml:3: materials[0].nir_785 must be a number");
    EXPECT_EQ(errorOf("[[materials]]\nnir_785 = 0.3\n"), "s.toml:1: missing field 'materials[0].name'");
    EXPECT_NE(errorOf("[[surfaces]]\nname = \"w\"\nmaterial = \"nope\"\n").find("names no material: 'nope'"),
              std::string::npos);
    EXPECT_NE(errorOf("[[sensors]]\ntype = \"velodyne\"\n").find("must be urg04lx or lms200"), std::string::npos);
    EXPECT_NE(
        errorOf("[[smoke]]\nname = \"x\"\ntype = \"vdb\"\nfile = \"missing.vdb\"\n").find("missing.vdb: no such file"),
        std::string::npos);
    EXPECT_NE(errorOf("[[smoke]]\nname = \"x\"\ntype = \"box\"\nmin = [0,0,0]\nmax = [1,1,-1]\n").find("s.toml:5"),
              std::string::npos);
    EXPECT_NE(errorOf("[[smoke]]\nname = \"x\"\ntype = \"box\"\nmin = [0,0,0]\nmax = [1,1,1]\n"
                      "timeline = { kind = \"keyframes\", keys = [[0, 1], [0, 2]] }\n")
                  .find("strictly"),
              std::string::npos);
    EXPECT_NE(errorOf("a = [1, 2\n").find("s.toml:"), std::string::npos);  // TOML syntax
    try {
        loadScene("bocass");
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()),
                  "bocass: no such scene file (built-in scenes: bocas, factory, factory_smoke, maze, plume)");
    }
}

TEST(Surfaces, PacketsOfFourGiveTheSingleRaysHits)
{
    // The plume scene's posts, trees, cart and walls from its lidar's place: every ray of a packet
    // (1 to 4 rays, misses and grazing edges among them) hits what it hits alone, at the same t.
    const Scene s = loadScene("plume");
    const SurfaceSet set(s);
    const Vec3 o(0.1, 0.05, 0.55);
    int hits = 0, misses = 0, compared = 0, beyond = 0;
    for (int i = 0; i < 4000; ++i) {
        Ray rays[4];
        const int n = 1 + i % 4;
        // Half the packets a beam's footprint (rays 1.5 mrad apart), half rays far apart from
        // origins a few centimetres apart; a range limit that cuts some hits off.
        const bool footprint = i % 2 == 0;
        for (int k = 0; k < n; ++k) {
            const int m = footprint ? i * 4 : i * 4 + k;
            const double az = 2 * M_PI * m / 16000.0 * 7.0 + (footprint ? 0.0015 * k : 0.0),
                         el = std::sin(0.37 * m) * 0.5 + (footprint ? 0.0015 * (k % 2) : 0.0);
            const Vec3 from = footprint ? o : o + Vec3(0.03 * k, -0.02 * k, 0.01 * k);
            rays[k] = Ray{from, Vec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el))};
        }
        const double t_max = i % 3 == 0 ? 5.0 : 30.0;
        SurfaceHit packet[4];
        set.closest4(rays, n, t_max, packet);
        for (int k = 0; k < n; ++k) {
            const SurfaceHit one = set.closest(rays[k], t_max);
            beyond += t_max == 5.0 && !one.hit && set.closest(rays[k], 30.0).hit;
            ASSERT_EQ(packet[k].material, one.material);
            ASSERT_EQ(packet[k].hit, one.hit) << i << " " << k;
            ASSERT_EQ(packet[k].surface, one.surface);
            ASSERT_EQ(packet[k].t_m, one.t_m) << i << " " << k;
            ASSERT_EQ(packet[k].normal, one.normal);
            (one.hit ? hits : misses) += 1;
            ++compared;
        }
    }
    EXPECT_GT(hits, compared / 8);
    EXPECT_GT(misses, compared / 10);
    EXPECT_GT(beyond, 50);  // hits the 5 m limit cut off
    SurfaceHit out[4];
    EXPECT_THROW(set.closest4(nullptr, 0, 1.0, out), Error);
    EXPECT_THROW(set.closest4(nullptr, 5, 1.0, out), Error);
}
