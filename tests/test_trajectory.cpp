// Robots driven through a scene (scene/trajectory.hpp): keyframed poses, and the sensors and
// cameras that ride on them.
#include <gtest/gtest.h>

#include <cmath>

#include "smokescan/core/error.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/scene/surfaces.hpp"
#include "smokescan/sensors/scanner.hpp"

using namespace smokescan;

namespace {
const char* kDrive = R"(
[[materials]]
name = "wall"
[[surfaces]]
name = "wall"
material = "wall"
type = "quad"
corner = [5, -5, -1]
u = [0, 10, 0]
v = [0, 0, 3]
[[robots]]
name = "p2dx"
[[robots.keyframes]]
time_s = 0
position = [0, 0, 0]
yaw_deg = 350
[[robots.keyframes]]
time_s = 10
position = [2, 0, 0]
yaw_deg = 10
[[robots.keyframes]]
time_s = 20
position = [2, 2, 0]
yaw_deg = 10
[[sensors]]
name = "laser"
type = "urg04lx"
robot = "p2dx"
position = [0.1, 0, 0.3]
[[cameras]]
name = "omni"
kind = "omni"
robot = "p2dx"
position = [0, 0, 0.931]
)";
}  // namespace

TEST(Trajectory, InterpolatesPositionAndHeadingAlongTheShorterArc)
{
    const Scene s = parseScene(kDrive, "drive.toml", "");
    ASSERT_EQ(s.robots.size(), 1u);
    const Robot& r = s.robots[0];
    // Halfway through the first leg: x = 1, heading 0 (350° → 10° the short way, not through 180°).
    const Pose mid = r.at(5);
    EXPECT_NEAR(mid.t.x(), 1.0, 1e-12);
    EXPECT_NEAR(mid.R(0, 0), 1.0, 1e-12);
    const Pose q = r.at(2.5);  // heading 355°
    EXPECT_NEAR(std::atan2(q.R(1, 0), q.R(0, 0)) * 180 / M_PI, -5.0, 1e-9);
    // Before the first and after the last keyframe the robot stands still.
    EXPECT_NEAR(r.at(-3).t.x(), 0.0, 1e-12);
    EXPECT_NEAR(r.at(99).t.y(), 2.0, 1e-12);
    EXPECT_NEAR(r.distanceAt(15), 3.0, 1e-12);
    EXPECT_NEAR(r.distanceAt(99), 4.0, 1e-12);
}

TEST(Trajectory, SensorsAndCamerasRideOnTheRobot)
{
    const Scene s = parseScene(kDrive, "drive.toml", "");
    const SurfaceSet surfaces(s);
    // The camera at t = 10 s: the robot at (2, 0), heading 10°; the camera 0.931 m up.
    const Camera c = s.cameraAt(s.cameras[0], 10);
    EXPECT_NEAR((c.pose.t - Vec3(2, 0, 0.931)).norm(), 0.0, 1e-12);
    // The laser 0.1 m ahead of the robot's origin: its straight-ahead beam meets the wall at x = 5.
    ScanConfig sc;
    sc.from_s = 0;
    sc.to_s = 10;
    sc.rate_hz = 0.1;
    const Scanner scanner(s, surfaces, sc);
    for (double t : {0.0, 10.0}) {
        const Scan scan = scanner.scanAt(t, 0);
        const int ahead = 384 - 44;  // step 384 is straight ahead
        const Pose p = s.robots[0].at(t);
        const double x0 = p.apply(Vec3(0.1, 0, 0.3)).x();
        const double yaw = std::atan2(p.R(1, 0), p.R(0, 0));
        EXPECT_NEAR(double(scan.value[size_t(ahead)]) / 1000, (5 - x0) / std::cos(yaw), 0.05) << "t " << t;
    }
}

TEST(Trajectory, BadRobotsAreRefused)
{
    auto refused = [](const std::string& text, const std::string& needle) {
        try {
            parseScene(text, "drive.toml", "");
            ADD_FAILURE() << "accepted: " << text;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("drive.toml"), std::string::npos) << e.what();
        }
    };
    const std::string k = "[[robots.keyframes]]\ntime_s = 0\n";
    refused("[[robots]]\nname = \"a\"\n", "at least one keyframe");
    refused("[[robots]]\nname = \"a\"\n" + k + "[[robots.keyframes]]\ntime_s = 0\n", "must exceed the previous");
    refused("[[robots]]\nname = \"a\"\n" + k + "[[robots]]\nname = \"a\"\n" + k, "repeats robot");
    refused("[[sensors]]\ntype = \"urg04lx\"\nrobot = \"ghost\"\n", "names no robot");
    refused("[[robots]]\nname = \"a\"\n[[robots.keyframes]]\ntime_s = 0\nyaw = 3\n", "yaw");
}
