// The omnicam colour-based rangefinder (omni/): its filters on hand-made scanlines, the colour
// histogram, and the whole chain on a rendered room with known wall distances.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "smokescan/core/error.hpp"
#include "smokescan/io/image.hpp"
#include "smokescan/omni/omni_plots.hpp"
#include "smokescan/omni/omni_rangefinder.hpp"
#include "smokescan/render/renderer.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/sensors/scanner.hpp"

#include "omni_court.hpp"
#include "sanitized.hpp"
#include "scratch.hpp"

using namespace smokescan;

namespace {
/// A scanline from text: '.' free, 'X' non-free, outwards.
std::vector<bool> line(const std::string& s)
{
    std::vector<bool> v;
    for (char c : s) v.push_back(c == '.');
    return v;
}
}  // namespace

TEST(OmniScanline, TheFiltersAsInThePapersFigure3)
{
    // Fig. 3a, N = 4: the first non-free pixel has a free one right behind it, so it is a false
    // positive; the hit is the first non-free pixel with four non-free ones behind it.
    EXPECT_EQ(findHitPoint(line("...X.XXXXX"), {4, 1}), 5);
    // Fig. 3b, K = 2: the lone free pixel between non-free ones is a false negative and negated,
    // so the obstacle starts at the first non-free pixel.
    EXPECT_EQ(findHitPoint(line("...X.XXXXX"), {4, 2}), 3);
    // A free run of K pixels breaks the obstacle: K = 2 keeps two free pixels.
    EXPECT_EQ(findHitPoint(line("...X..XXXXX"), {4, 2}), 6);
    EXPECT_EQ(findHitPoint(line("...X..XXXXX"), {4, 3}), 3);
}

TEST(OmniScanline, EdgesOfTheLine)
{
    EXPECT_EQ(findHitPoint(line(".........."), {4, 2}), -1);  // all free
    EXPECT_EQ(findHitPoint(line("XXXXXXXXXX"), {4, 2}), 0);  // blocked from the first pixel
    EXPECT_EQ(findHitPoint(line("......XXXX"), {4, 2}), -1);  // only 3 behind: not confirmed
    EXPECT_EQ(findHitPoint(line(".....XXXXX"), {4, 2}), 5);  // exactly N behind
    // A short free run at the very start or end is not between obstacles: not negated.
    EXPECT_EQ(findHitPoint(line(".XXXXX"), {4, 2}), 1);
    EXPECT_EQ(findHitPoint(line("XXXX."), {4, 2}), -1);
    EXPECT_EQ(findHitPoint({}, {4, 2}), -1);
    EXPECT_THROW(findHitPoint(line("X"), {0, 2}), Error);
    EXPECT_THROW(findHitPoint(line("X"), {4, 0}), Error);
}

TEST(OmniHistogram, ClassifiesHeldOutPixelsAsTheCountsSay)
{
    // A floor of three colours in known proportions: 70 % green, 26 % brown, 4 % yellow.
    ColourHistogram h;
    for (int i = 0; i < 700; ++i) h.add(0.20f + 0.0001f * (i % 50), 0.55f, 0.15f);
    for (int i = 0; i < 260; ++i) h.add(0.45f, 0.30f, 0.12f + 0.0001f * (i % 50));
    for (int i = 0; i < 40; ++i) h.add(0.90f, 0.85f, 0.10f);
    EXPECT_EQ(h.total(), 1000u);
    // 13 bins per channel, width 1/13: 0.20 and 0.2049 share bin 2; 0.55 is bin 7.
    EXPECT_EQ(h.count(2, 7, 1), 700u);
    // Held-out pixels: other values in the same bins read the same share.
    EXPECT_DOUBLE_EQ(h.share(0.16f, 0.60f, 0.08f), 0.70);
    EXPECT_DOUBLE_EQ(h.share(0.42f, 0.27f, 0.09f), 0.26);
    EXPECT_DOUBLE_EQ(h.share(0.91f, 0.88f, 0.14f), 0.04);
    EXPECT_DOUBLE_EQ(h.share(0.5f, 0.5f, 0.5f), 0.0);
    // Θ = 0.05 (the maze's): green and brown are free, yellow (4 %) and grey are not.
    EXPECT_TRUE(h.isFree(0.16f, 0.60f, 0.08f, 0.05));
    EXPECT_TRUE(h.isFree(0.42f, 0.27f, 0.09f, 0.05));
    EXPECT_FALSE(h.isFree(0.91f, 0.88f, 0.14f, 0.05));
    EXPECT_FALSE(h.isFree(0.5f, 0.5f, 0.5f, 0.05));
    // Θ = 0.3: only green.
    EXPECT_FALSE(h.isFree(0.42f, 0.27f, 0.09f, 0.3));
    // The ends of the range fall in the first and last bins.
    ColourHistogram e(13);
    e.add(1.0f, 0.0f, -0.5f);
    EXPECT_EQ(e.count(12, 0, 0), 1u);
}

TEST(OmniHistogram, SavesLoadsAndRefusesBadFiles)
{
    namespace fs = std::filesystem;
    const fs::path dir = test::scratch("omni_hist");
    ColourHistogram h(13);
    h.add(0.2f, 0.5f, 0.1f);
    h.add(0.2f, 0.5f, 0.1f);
    h.add(0.9f, 0.1f, 0.1f);
    h.save((dir / "h.txt").string());
    const ColourHistogram back = ColourHistogram::load((dir / "h.txt").string());
    EXPECT_EQ(back.total(), 3u);
    EXPECT_DOUBLE_EQ(back.share(0.2f, 0.5f, 0.1f), 2.0 / 3.0);
    EXPECT_EQ(back.exposure(), 0.0);  // unknown stays unknown
    h.setExposure(1.0 / 3.0);  // the frames' exposure travels with the counts, exactly
    h.save((dir / "h.txt").string());
    EXPECT_EQ(ColourHistogram::load((dir / "h.txt").string()).exposure(), 1.0 / 3.0);
    EXPECT_THROW(h.setExposure(-1), Error);
    auto refused = [&](const std::string& text, const std::string& needle) {
        std::ofstream((dir / "bad.txt").string()) << text;
        try {
            ColourHistogram::load((dir / "bad.txt").string());
            ADD_FAILURE() << "accepted: " << text;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("bad.txt"), std::string::npos) << e.what();
        }
    };
    const std::string head = "# smokescan colour histogram v1, bins per channel: 13\n";
    refused("r g b count\n", "not a smokescan colour histogram");
    refused("# smokescan colour histogram v1, bins per channel: 0\n", "1…64");
    refused(head + "1 2 13 5\n", "bin outside");
    refused(head + "1 2 3 5\n1 2 3 1\n", "given twice");
    refused(head + "1 2 3 0\n", "positive integer");
    refused(head + "1 2 3\n", "expected 'r g b count'");
    refused(head, "no counts");
    refused(head + "# exposure -2\n1 2 3 5\n", "exposure must be a number in [1e-6, 1e6]");
    refused(head + "# exposure 1 2\n1 2 3 5\n", "exposure must be a number in [1e-6, 1e6]");
    refused(head + "# exposure 5e-324\n1 2 3 5\n", "bad.txt:2: exposure must be a number in [1e-6, 1e6]");
    refused(head + "# exposure 2\n1 2 3 5\n# exposure 3\n", "bad.txt:4: exposure given twice");
    fs::remove_all(dir);
}

TEST(OmniRangefinder, ReadsTheWallsOfARenderedRoomWithinAPixel)
{
    const Scene scene = parseScene(test::omniCourt(), "omni_room.toml", "");
    const SurfaceSet surfaces(scene);
    const auto model = makeCamera(scene.cameras[0]);
    const auto& cam = dynamic_cast<const OmniCamera&>(*model);
    RenderConfig rc;
    rc.spp = 16;
    rc.progress = false;
    const Image frame = toDisplay(render(scene, surfaces, rc).radiance, 1.0);

    // Train on the Sick's scan at the same pose: free floor inside its measured ranges.
    ScanConfig sc;
    sc.sensor = "sick";
    const Scanner scanner(scene, surfaces, sc);
    const Scan s = scanner.scanAt(0, 0);
    LaserFreeSpace laser;
    laser.pose.t = Vec3(0, 0, 0.3);
    for (int i = 0; i < scanner.spec().n_beams; ++i) {
        const Vec3 d = scanner.beamRay(i).d;
        laser.angle_rad.push_back(std::atan2(d.y(), d.x()));
        laser.range_m.push_back(s.beams[size_t(i)].error ? NAN : double(s.value[size_t(i)]) / 1000.0);
    }
    ASSERT_LT(laser.angle_rad.front(), laser.angle_rad.back());
    OmniRangeConfig cfg;
    cfg.height_m = 0.931;
    ColourHistogram hist;
    EXPECT_GT(trainFreeSpace(hist, frame, cam, laser, cfg), 2000);  // the front half, 0.1 m clear of the walls

    // Every direction, also behind the laser: the nearest wall along the azimuth (the court is
    // asymmetric both ways, so a turned or mirrored image would miss). The scanlines
    // sample whole pixels, so a reading is within one pixel's metric error at that range but for
    // the quantisation's and the render noise's unlucky cases: 95 % within one, all within two,
    // and no bias beyond half a pixel.
    const OmniRangeResult r = omniRange(frame, cam, hist, cfg);
    ASSERT_EQ(r.range_m.size(), 360u);
    int within = 0;
    double err_px = 0;
    for (size_t i = 0; i < r.range_m.size(); ++i) {
        const double phi = r.angle_rad[i];
        const double truth = test::courtWall(phi);
        const double rho = cam.radius(std::atan2(truth, cfg.height_m));
        const double pixel_m = cam.floorDistance(rho + 1, cfg.height_m) - truth;
        ASSERT_EQ(r.status[i], OmniRangeStatus::Hit) << "azimuth " << phi;
        within += std::abs(r.range_m[i] - truth) <= pixel_m;
        EXPECT_LE(std::abs(r.hit_radius_px[i] - rho), 2.0) << "azimuth " << phi;
        err_px += (r.hit_radius_px[i] - rho) / 360;
    }
    std::printf("%d of 360 scanlines within a pixel, mean error %+.2f px\n", within, err_px);
    EXPECT_GE(within, 342) << "of 360 scanlines within a pixel";
    EXPECT_LT(std::abs(err_px), 0.5) << "mean error [px]";
    // The same frame with the walls' colour trained as free: no scanline finds a wall.
    ColourHistogram walls;
    for (int y = 0; y < frame.height; ++y)
        for (int x = 0; x < frame.width; ++x) walls.add(frame.at(x, y, 0), frame.at(x, y, 1), frame.at(x, y, 2));
    OmniRangeConfig lax = cfg;
    lax.threshold = 1e-6;
    for (OmniRangeStatus st : omniRange(frame, cam, walls, lax).status) EXPECT_EQ(st, OmniRangeStatus::MaxRange);
}

TEST(OmniRangefinder, RefusesConfigurationsThatCannotWork)
{
    const OmniCamera cam(Pose::fromRpyDeg(Vec3(0, 0, 0.931), Vec3::Zero()), OmniIntrinsics{});
    const ColourHistogram hist;
    const Image frame(1024, 768, 3);
    auto refused = [&](OmniRangeConfig c, const std::string& needle) {
        try {
            omniRange(frame, cam, hist, c);
            ADD_FAILURE() << "accepted " << needle;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    OmniRangeConfig c;
    c.threshold = 0;
    refused(c, "threshold");
    c = {};
    c.threshold = 1.5;
    refused(c, "threshold");
    c = {};
    c.filter.n_behind = 0;
    refused(c, "--n-behind");
    c = {};
    c.filter.k_free = 0;
    refused(c, "--k-free");
    // A mirror that puts the floor at 3.8 m outside the frame (R = 600 px: radius 470 px), or
    // a rim that stops short of it (60°, where 3.8 m lies at 76°).
    OmniIntrinsics big;
    big.mirror_radius = 600;
    big.max_incidence_deg = 100;
    EXPECT_THROW(checkOmniRangeConfig({}, OmniCamera(Pose{}, big)), Error);
    OmniIntrinsics based;
    based.base_radius = 160;  // hides the floor out to 4.4 m
    EXPECT_THROW(checkOmniRangeConfig({}, OmniCamera(Pose{}, based)), Error);
    OmniIntrinsics narrow;
    narrow.max_incidence_deg = 60;
    try {
        checkOmniRangeConfig({}, OmniCamera(Pose{}, narrow));
        ADD_FAILURE() << "accepted a rim short of the floor";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("outside the image or the mirror's rim"), std::string::npos) << e.what();
    }
    c = {};
    c.max_range_m = 1e5;  // beyond what a laser log holds
    refused(c, "--max-range");
    c = {};
    c.min_range_m = 4;
    refused(c, "--min-range");
    c = {};
    c.height_m = -1;
    refused(c, "above the floor");
    EXPECT_THROW(omniRange(Image(640, 480, 3), cam, hist, OmniRangeConfig{}), Error);  // another size
}

TEST(OmniPlots, OccupancyGridsMarkWallsFreeSpaceAndTheUnknown)
{
    // One frame: both sensors at the origin read a circle of radius 2 m (the laser over its front
    // half, the omnicam all round): cells at 2 m are occupied (black), at 1 m free (white), behind
    // the laser unknown in its panel (grey) but free in the omnicam's.
    OmniFrame f;
    for (int i = 0; i < 181; ++i) {
        f.laser_angle_rad.push_back((i - 90) * M_PI / 180);
        f.laser_range_m.push_back(2.0);
    }
    for (int i = 0; i < 360; ++i) {
        f.omni.angle_rad.push_back(std::remainder(i * M_PI / 180, 2 * M_PI));
        f.omni.range_m.push_back(2.0);
        f.omni.status.push_back(OmniRangeStatus::Hit);
        f.omni.hit_radius_px.push_back(50);
    }
    const std::string path = (test::scratch("omni_map") / "map.png").string();
    OccupancyConfig cfg;
    cfg.cell_m = 0.1;
    writeOccupancyGrids(path, {f}, cfg);
    const Image m = readImage(path);
    // The area: ±2 m and half a metre round: 50 cells a side; the panels 10 px apart.
    ASSERT_EQ(m.height, 50);
    ASSERT_EQ(m.width, 2 * 50 + 10);
    auto at = [&](int panel, double x, double y) {
        const int i = int(std::floor((x + 2.5) / 0.1)), j = int(std::floor((2.5 - y) / 0.1));
        return m.at(panel * 60 + i, j, 1);
    };
    for (int p = 0; p < 2; ++p) {
        EXPECT_LT(at(p, 1.99, 0.05), 0.2f) << "panel " << p;  // the wall ahead
        EXPECT_GT(at(p, 1.0, 0.05), 0.9f) << "panel " << p;  // free
        EXPECT_NEAR(at(p, 2.3, 0.05), 0.75f, 0.05f) << "panel " << p;  // beyond the wall: unknown
    }
    EXPECT_NEAR(at(0, -1.0, 0.05), 0.75f, 0.05f);  // behind the laser: unknown
    EXPECT_GT(at(1, -1.0, 0.05), 0.9f);  // the omnicam sees all round
    EXPECT_THROW(writeOccupancyGrids(path, {}, cfg), Error);
    // The histogram of differences writes a picture.
    writeDifferenceHistogram((test::scratch("omni_map") / "fig9.png").string(), {0.01, -0.02, 0.3}, 1.25, "test");
    EXPECT_GT(readImage((test::scratch("omni_map") / "fig9.png").string()).width, 100);
}
