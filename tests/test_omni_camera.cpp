// The catadioptric omnidirectional camera (render/omni_camera.hpp) against its closed form.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "smokescan/core/error.hpp"
#include "smokescan/core/random.hpp"
#include "smokescan/omni/birdseye.hpp"
#include "smokescan/render/omni_camera.hpp"
#include "smokescan/render/renderer.hpp"
#include "smokescan/scene/scene_io.hpp"

using namespace smokescan;

namespace {
/// The paper's camera (1024×768, R = 192 px) with its viewpoint 0.931 m above the floor at
/// (1, 2), turned 30° about the vertical.
OmniCamera papersCamera() { return OmniCamera(Pose::fromRpyDeg(Vec3(1, 2, 0.931), Vec3(0, 0, 30)), OmniIntrinsics{}); }

/// Where a ray meets the floor z = 0 (its distance along the ray).
double floorHit(const Ray& r) { return -r.o.z() / r.d.z(); }
}  // namespace

TEST(OmniCamera, AFloorPointLandsWhereTheMirrorEquationSays)
{
    // A floor point 2 m away at a world bearing of 40°, i.e. 10° left of the camera's +x:
    // θ = atan(2/0.931) from straight down, ρ = R·tan(θ/2), the point at (cx + ρ cos 10°,
    // cy − ρ sin 10°).
    const OmniCamera cam = papersCamera();
    const double b = 40 * M_PI / 180;
    const Vec3 p(1 + 2 * std::cos(b), 2 + 2 * std::sin(b), 0);
    const double theta = std::atan(2 / 0.931), rho = 192 * std::tan(theta / 2), phi = 10 * M_PI / 180;
    const Vec2 px = cam.project(p);
    EXPECT_NEAR(px.x(), 512 + rho * std::cos(phi), 1e-9);
    EXPECT_NEAR(px.y(), 384 - rho * std::sin(phi), 1e-9);
    // The ray through that pixel meets the floor at the point (sub-pixel: to 1e-9 m).
    Ray r;
    ASSERT_TRUE(cam.generateRay(px.x(), px.y(), r));
    EXPECT_LT((r.at(floorHit(r)) - p).norm(), 1e-9);
}

TEST(OmniCamera, RaysAndProjectionsRoundTrip)
{
    const OmniCamera cam = papersCamera();
    KeyedRng rng(3, 0, 0);
    int inside = 0;
    for (int k = 0; k < 2000; ++k) {
        const double x = 1024 * rng.uniform(), y = 768 * rng.uniform();
        Ray r;
        if (!cam.generateRay(x, y, r)) continue;
        ++inside;
        EXPECT_NEAR(r.d.norm(), 1.0, 1e-12);
        const Vec2 back = cam.project(r.at(3.7));
        EXPECT_NEAR(back.x(), x, 1e-8);
        EXPECT_NEAR(back.y(), y, 1e-8);
    }
    // The mirror's disc (rim at 110°: ρ = 192·tan 55° = 274 px) within the 1024×768 frame.
    const double disc = M_PI * std::pow(192 * std::tan(55 * M_PI / 180), 2) / (1024.0 * 768.0);
    EXPECT_NEAR(inside / 2000.0, disc, 4 * std::sqrt(disc * (1 - disc) / 2000));
}

TEST(OmniCamera, FloorDistanceIsHeightTimesTanThetaAtThePapersMount)
{
    // d = h·tan θ with θ = 2·arctan(ρ/R), h = 0.931 m, R = 192 px: the 90° circle is the horizon
    // (d infinite), and the paper's 3.8 m maximum range lies at ρ ≈ 150.6 px (θ = 76.2°).
    const OmniCamera cam = papersCamera();
    EXPECT_NEAR(cam.floorDistance(150.6, 0.931), 3.80, 0.01);
    EXPECT_EQ(cam.floorDistance(192, 0.931), kInf);
    EXPECT_EQ(cam.floorDistance(250, 0.931), kInf);
    EXPECT_DOUBLE_EQ(cam.floorDistance(0, 0.931), 0.0);
    // Against the geometry: the ray through radius ρ (to the right of the centre) meets the floor
    // at that horizontal distance from the point below the viewpoint.
    for (double rho = 5; rho < 190; rho += 7.3) {
        Ray r;
        ASSERT_TRUE(cam.generateRay(512 + rho, 384, r));
        const Vec3 p = r.at(floorHit(r));
        EXPECT_NEAR(std::hypot(p.x() - 1, p.y() - 2), cam.floorDistance(rho, 0.931), 1e-9 * (1 + p.norm()));
    }
    // One pixel's metric error grows hyperbolically (the paper's Fig. 8): 1.8 cm at 1 m, 10.9 cm at 3.8 m.
    EXPECT_NEAR(cam.floorDistance(151.6, 0.931) - cam.floorDistance(150.6, 0.931), 0.109, 0.002);
    const double rho1 = cam.radius(std::atan(1 / 0.931));  // 1 m away
    EXPECT_NEAR(cam.floorDistance(rho1 + 1, 0.931) - 1.0, 0.018, 0.001);
}

TEST(OmniCamera, TheRimAndTheBaseSeeNothing)
{
    OmniIntrinsics k;
    k.base_radius = 40;
    const OmniCamera cam(Pose{}, k);
    Ray r;
    EXPECT_FALSE(cam.generateRay(512 + 30, 384, r));  // on the base
    EXPECT_TRUE(cam.generateRay(512 + 50, 384, r));
    EXPECT_TRUE(cam.generateRay(512, 384 - 270, r));  // inside the rim (274 px)
    EXPECT_FALSE(cam.generateRay(512, 384 - 280, r));
    EXPECT_FALSE(cam.generateRay(0, 0, r));
}

TEST(OmniCamera, AutoExposureMetersTheMirrorDiscOnly)
{
    // Where the camera sees: radiance 0.5, but black on the disc's right half (x > centre); where
    // it sees nothing (the frame round the disc, the base): bright 5.0. Metered over what the
    // camera sees, the mean is 0.5 × the left half's share of the seen pixels; a meter over
    // non-black pixels, or over the whole frame, gives other scales.
    OmniIntrinsics k;
    k.base_radius = 40;
    const OmniCamera cam(Pose{}, k);
    Image rad(k.width, k.height, 3);
    Ray r;
    long long seen = 0, lit = 0;
    for (int y = 0; y < rad.height; ++y)
        for (int x = 0; x < rad.width; ++x) {
            const bool sees = cam.generateRay(x + 0.5, y + 0.5, r);
            const float v = !sees ? 5.0f : x + 0.5 > k.cx ? 0.0f : 0.5f;
            seen += sees;
            lit += sees && v > 0;
            for (int c = 0; c < 3; ++c) rad.at(x, y, c) = v;
        }
    ASSERT_GT(lit, seen / 3);
    ASSERT_LT(lit, 2 * seen / 3);
    double used = 0;
    toDisplay(rad, 0.0, &used, &cam);
    EXPECT_NEAR(used, 0.18 / (0.5 * double(lit) / double(seen)), 1e-9);
    const double frame_mean =
        (0.5 * double(lit) + 5.0 * (double(rad.width) * rad.height - double(seen))) / (double(rad.width) * rad.height);
    toDisplay(rad, 0.0, &used);  // the whole frame, as a pinhole camera meters
    EXPECT_NEAR(used, 0.18 / frame_mean, 1e-9);
    toDisplay(rad, 2.0, &used, &cam);  // a given exposure is kept
    EXPECT_EQ(used, 2.0);
    // A frame the mirror's disc misses entirely cannot be metered (it is not metered as black).
    OmniIntrinsics off = k;
    off.cx = 5000;
    const OmniCamera far(Pose{}, off);
    EXPECT_THROW(toDisplay(rad, 0.0, &used, &far), Error);
}

TEST(OmniCamera, SceneFilesMakeOmniCamerasAndRefuseBadMirrors)
{
    const std::string head = "[[cameras]]\nname = \"omni\"\nposition = [0, 0, 0.931]\n";
    const Scene s =
        parseScene(head + "kind = \"omni\"\nwidth = 1024\nheight = 768\nbase_radius_px = 30\n", "omni.toml", "");
    ASSERT_EQ(s.cameras.size(), 1u);
    EXPECT_EQ(s.cameras[0].kind, CameraKind::Omni);
    const auto cam = makeCamera(s.cameras[0]);
    Ray r;
    ASSERT_TRUE(cam->generateRay(512 + 192, 384, r));  // the 90° circle: horizontal
    EXPECT_NEAR(r.d.z(), 0.0, 1e-12);
    EXPECT_NEAR(r.d.x(), 1.0, 1e-12);
    auto refused = [&](const std::string& extra, const std::string& needle) {
        try {
            parseScene(head + (extra.rfind("kind", 0) == 0 ? "" : "kind = \"omni\"\n") + extra, "omni.toml", "");
            ADD_FAILURE() << "accepted: " << extra;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("omni.toml"), std::string::npos) << e.what();
        }
    };
    refused("mirror_radius_px = 0\n", "mirror_radius_px");
    refused("max_incidence_deg = 175\n", "max_incidence_deg");
    refused("base_radius_px = 400\n", "hides the whole mirror");
    refused("kind = \"fisheye\"\n", "pinhole or omni");
    refused("cx_px = -200\n", "cx_px");  // not taken for "unset" (the centre)
    refused("cy_px = 1e9\n", "cy_px");
}

TEST(OmniCamera, TheBirdseyeViewPutsEachFloorPointWhereItLies)
{
    // A synthetic frame whose every pixel shows the floor point its ray meets, painted as a 0.5 m
    // checkerboard (white and black): the bird's-eye view shows the same checkerboard, each output
    // pixel the square of its own floor point, except within a pixel of the squares' edges.
    const OmniCamera cam(Pose::fromRpyDeg(Vec3(0.3, -0.2, 0.931), Vec3(0, 0, 25)), OmniIntrinsics{});
    auto square = [](double x, double y) { return (int(std::floor(x / 0.5)) + int(std::floor(y / 0.5))) & 1; };
    Image frame(1024, 768, 3);
    for (int y = 0; y < 768; ++y)
        for (int x = 0; x < 1024; ++x) {
            Ray r;
            if (!cam.generateRay(x + 0.5, y + 0.5, r) || !(r.d.z() < 0)) continue;
            const Vec3 p = r.at(-r.o.z() / r.d.z());
            for (int k = 0; k < 3; ++k) frame.at(x, y, k) = float(square(p.x(), p.y()));
        }
    BirdseyeConfig bc;
    bc.size_px = 300;
    bc.metres_per_px = 0.02;  // 6 m × 6 m
    const Image view = birdseye(frame, cam, bc);
    int checked = 0, agree = 0;
    for (int j = 0; j < 300; ++j)
        for (int i = 0; i < 300; ++i) {
            const Vec3 p = cam.pose().apply(Vec3((i + 0.5 - 150) * 0.02, (150 - j - 0.5) * 0.02, -0.931));
            const double fx = p.x() / 0.5 - std::floor(p.x() / 0.5), fy = p.y() / 0.5 - std::floor(p.y() / 0.5);
            if (std::min({fx, 1 - fx, fy, 1 - fy}) < 0.1) continue;  // near an edge: mixed by the sampling
            if (std::hypot(p.x() - 0.3, p.y() + 0.2) > 2.5) continue;  // far out a pixel spans several cm
            ++checked;
            agree += std::abs(view.at(i, j, 0) - float(square(p.x(), p.y()))) < 0.5f;
        }
    EXPECT_GT(checked, 20000);
    EXPECT_EQ(agree, checked);
    EXPECT_THROW(birdseye(frame, cam, BirdseyeConfig{0, 0.01, 0.9}), Error);
    EXPECT_THROW(birdseye(Image(10, 10, 3), cam, bc), Error);
}
