// `smokescan fit` on the omnicam's log: its readings against the scene's truth, the walls as
// groups, the onset of wrong readings against the camera's saturation, and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "cli_run.hpp"
#include "omni_fit_run.hpp"
#include "smokescan/calib/calibration.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/order_stats.hpp"
#include "smokescan/fit/omni_fit.hpp"

using namespace smokescan;
using namespace smokescan::test;

namespace {

/// The planted run's files, and the fit's inputs for them.
FitInputsConfig plantedFiles(unsigned seed, const std::string& tag)
{
    const PlantedOmniRun run = plantOmniRun(seed);
    FitInputsConfig c;
    c.laser = file("planted_" + tag + ".log", run.log_text);
    c.saturation = file("planted_" + tag + ".csv", run.saturation_text);
    c.scene = file("court_fit.toml", omniCourt());
    c.prefix = "wall_";
    return c;
}

}  // namespace

TEST(OmniFit, ClassifiesEachReadingAgainstItsTruthAndGroupsTheWallsByTheirLinesOfSight)
{
    const OmniFitInputs o = loadOmniFitInputs(plantedFiles(1, "classify"), OmniFitConfig{});
    EXPECT_EQ(o.camera, "omni");
    EXPECT_NEAR(o.height_m, 0.931, 1e-9);
    ASSERT_EQ(o.failed.size(), 301u);
    // Per wall, the interior scanlines (both neighbours on the same wall) by the court's closed form.
    std::map<std::string, std::vector<double>> sight;
    for (int i = 1; i < 359; ++i) {
        const double b = i * M_PI / 180;
        const std::string w = courtWallName(b);
        if (courtWallName(b - M_PI / 180) == w && courtWallName(b + M_PI / 180) == w)
            sight[w].push_back(std::hypot(courtWall(b), 0.931));
        EXPECT_NEAR(o.truth_m[size_t(i)], courtWall(b), 2e-3) << "scanline " << i;
    }
    ASSERT_EQ(o.in.groups.size(), 4u);
    for (const BeamGroup& g : o.in.groups) {
        ASSERT_TRUE(sight.count(g.name)) << g.name;
        EXPECT_EQ(g.intervals_rad.size(), sight[g.name].size()) << g.name;
        EXPECT_NEAR(g.range_m, median(sight[g.name]), 2e-3) << g.name;
    }
    // Clear air (S = 0.35 at t = 0): no scanline fails; at t = 150 s (S = 0.05) every east and
    // west one does, short and long, and no north or south one.
    int clear = 0, east = 0, west = 0, other = 0;
    for (int i = 0; i < 360; ++i) {
        clear += o.failed[0][size_t(i)];
        const std::string w = courtWallName(i * M_PI / 180);
        (w == "wall_east" ? east : w == "wall_west" ? west : other) += o.failed[150][size_t(i)];
    }
    EXPECT_EQ(clear, 0);
    EXPECT_EQ(other, 0);
    EXPECT_GT(east, 60);
    EXPECT_GT(west, 40);
    EXPECT_GT(o.shorter, 0);
    EXPECT_GT(o.longer, 0);
    EXPECT_EQ(o.readings, 301 * 360);
}

TEST(OmniFit, RecoversEachWallsPlantedOnsetAndItsPenetrationPowerAlongTheLineOfSight)
{
    const CurveFitResult calib = readCalibrationJson("bocas");
    int within = 0, fits = 0;
    for (unsigned seed = 1; seed <= 5; ++seed) {
        const OmniFitInputs o = loadOmniFitInputs(plantedFiles(seed, "recover"), OmniFitConfig{});
        const SensorFitResult r =
            fitSensor(o.in.log, o.in.saturation, o.in.groups, o.spec, &o.in.calibration, SensorFitConfig{}, o.failed);
        ASSERT_TRUE(r.ok()) << "seed " << seed;
        EXPECT_LT(std::abs(r.offset.offset_s.value), 1.0) << "seed " << seed;
        for (size_t g = 0; g < r.thresholds.size(); ++g) {
            const ThresholdFit& th = r.thresholds[g];
            const auto planted = PlantedOmniRun{}.S_star;
            if (!planted.count(th.group)) {
                EXPECT_FALSE(th.fitted) << th.group << ": it never fails";
                EXPECT_EQ(th.errors, 0) << th.group;
                continue;
            }
            ASSERT_TRUE(th.fitted) << th.group << " " << th.diagnosis;
            ++fits;
            within += std::abs(th.S_star.value - planted.at(th.group)) < 2 * th.S_star.se;
            EXPECT_LT(std::abs(th.S_star.value - planted.at(th.group)), 4 * th.S_star.se + 1e-3) << th.group;
            // P is the density at S* times the line of sight to the wall's foot, not the horizontal distance.
            EXPECT_NEAR(th.penetration_power.value, calib.curve.invert(th.S_star.value) * o.in.groups[g].range_m, 1e-9);
            EXPECT_GT(o.in.groups[g].range_m, 1.5);
        }
    }
    // Ten fits: at 2 SE about 95 % land within; 7 or more (binomial tail under 0.2 %).
    EXPECT_GE(within, 7) << "of " << fits;
}

TEST(OmniFit, RefusesMovingCamerasRangedGroupsAndFailureMasksOfAnotherShape)
{
    FitInputsConfig c = plantedFiles(1, "refuse");
    std::string moving = omniCourt();
    moving.replace(moving.find("time_s = 0\n"), 11,
                   "time_s = 0\n[[robots.keyframes]]\ntime_s = 2\nposition = [0.5, 0, 0]\n");
    c.scene = file("court_moving.toml", moving);
    EXPECT_THROW(
        {
            try {
                loadOmniFitInputs(c, OmniFitConfig{});
            } catch (const Error& e) {
                EXPECT_NE(std::string(e.what()).find("moving camera"), std::string::npos) << e.what();
                throw;
            }
        },
        Error);
    c = plantedFiles(1, "refuse");
    c.surfaces = {"east=-10:10@1.5"};
    EXPECT_THROW(loadOmniFitInputs(c, OmniFitConfig{}), Error);
    c.surfaces = {"east=-10:10"};
    const OmniFitInputs o = loadOmniFitInputs(c, OmniFitConfig{});
    ASSERT_EQ(o.in.groups.size(), 1u);
    EXPECT_NEAR(o.in.groups[0].range_m, std::hypot(1.5, 0.931), 0.01);
    FailureMask wrong = o.failed;
    wrong.pop_back();
    EXPECT_THROW(fitSensor(o.in.log, o.in.saturation, o.in.groups, o.spec, &o.in.calibration, {}, wrong), Error);
    OmniFitConfig bad;
    bad.tolerance_m = 0;
    EXPECT_THROW(loadOmniFitInputs(c, bad), Error);
    bad = OmniFitConfig{};
    bad.floor_z_m = 1.0;  // above the camera
    EXPECT_THROW(loadOmniFitInputs(c, bad), Error);
    bad = OmniFitConfig{};
    bad.max_range_m = 0.5;  // most readings beyond it: the wrong unit or range
    EXPECT_THROW(loadOmniFitInputs(c, bad), Error);
}

TEST(OmniFitCli, WritesTheOmnicamsOnsetWhichScanRefuses)
{
    const FitInputsConfig c = plantedFiles(2, "cli");
    const std::string out = file("omni_fit.toml"), report = file("omni_fit_report.json");
    const std::string args = "fit --laser " + c.laser + " --saturation " + c.saturation + " --scene " + c.scene +
        " --sensor-type omnicam --target-prefix wall_ --out " + out;
    const CliRun r = cli(args);
    ASSERT_EQ(r.status, 0) << r.err << r.out;
    EXPECT_NE(r.out.find("omnicam 'omni', viewpoint 0.931 m above the floor"), std::string::npos) << r.out;
    const std::string toml = slurp(out);
    EXPECT_NE(toml.find("type = \"omnicam\""), std::string::npos) << toml;
    EXPECT_NE(toml.find("penetration_power = "), std::string::npos) << toml;
    EXPECT_TRUE(std::filesystem::exists(report));
    expectBad("scan " + c.scene + " --sensor-file " + out + " --out " + file("never.log"), "omnicam",
              file("never.log"));
    const std::string no = file("never.toml");
    expectBad("fit --laser " + c.laser + " --saturation " + c.saturation +
                  " --sensor-type omnicam --surface e=0:10 --out " + no,
              "needs --scene", no);
    expectBad(args.substr(0, args.find(" --out")) + " --tolerance 0 --out " + no, "--tolerance", no);
    expectBad("fit --laser " + c.laser + " --saturation " + c.saturation +
                  " --sensor-type urg04lx --surface e=0:10 "
                  "--tolerance 0.5 --out " +
                  no,
              "omnicam", no);
}
