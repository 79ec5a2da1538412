// `smokescan fit` on the omnicam's log: its readings against the scene's truth, the walls as
// groups, the onset of wrong readings against the camera's saturation, and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <sstream>

#include "cli_run.hpp"
#include "error_of.hpp"
#include "omni_fit_run.hpp"
#include "smokescan/calib/calibration.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/order_stats.hpp"
#include "smokescan/fit/omni_fit.hpp"
#include "smokescan/sensor_config/sensor_file.hpp"

using namespace smokescan;
using namespace smokescan::test;

namespace {

/// The planted run's files, and the fit's inputs for them.
FitInputsConfig plantedFiles(const PlantedOmniRun& run, const std::string& tag, const std::string& scene)
{
    FitInputsConfig c;
    c.laser = file("planted_" + tag + ".log", run.log_text);
    c.saturation = file("planted_" + tag + ".csv", run.saturation_text);
    c.scene = file("court_" + tag + ".toml", scene);
    c.prefix = "wall_";
    return c;
}

FitInputsConfig plantedFiles(unsigned seed, const std::string& tag)
{
    return plantedFiles(plantOmniRun(seed), tag, omniCourt());
}

/// The planted run's log (seed 1) rewritten scanline by scanline: `pair(i, bearing, reading)`
/// gives what follows the scan's time for scanline i (its fields as written; "" drops it).
std::string rewrittenLog(const std::function<std::string(int, const std::string&, const std::string&)>& pair)
{
    std::string text;
    std::istringstream lines(plantOmniRun(1).log_text);
    for (std::string line; std::getline(lines, line);) {
        std::istringstream f(line);
        std::string t, a, r;
        f >> t;
        text += t;
        for (int i = 0; f >> a >> r; ++i) text += pair(i, a, r);
        text += "\n";
    }
    return text;
}

/// The planted run's log (seed 1) with its bearings turned by `turn_rad`, each scanline split
/// into `split` reading the truth at their own bearings (clear air); in c's other files.
FitInputsConfig relogged(const FitInputsConfig& c, double turn_rad, int split)
{
    const std::string text = rewrittenLog([&](int, const std::string& a, const std::string& r) {
        std::string out;
        for (int j = 0; j < split; ++j) {
            const double b = std::remainder(std::stod(a) + j * M_PI / 180 / split + turn_rad, 2 * M_PI);
            const double reading = split == 1 ? std::stod(r) : 1000 * courtWall(std::stod(a) + j * M_PI / 180 / split);
            char buf[64];
            std::snprintf(buf, sizeof buf, " %.6f %lld", b, std::llround(reading));
            out += buf;
        }
        return out;
    });
    FitInputsConfig out = c;
    out.laser = file("relogged_" + std::to_string(split) + "_" + std::to_string(turn_rad) + ".log", text);
    return out;
}

}  // namespace

TEST(OmniFit, ClassifiesEachReadingAgainstItsTruthAndGroupsTheWallsByTheirLinesOfSight)
{
    const PlantedOmniRun run = plantOmniRun(1);
    const OmniFitInputs o = loadOmniFitInputs(plantedFiles(run, "classify", omniCourt()), OmniFitConfig{});
    EXPECT_EQ(o.camera, "omni");
    EXPECT_NEAR(o.height_m, 0.931, 1e-9);
    ASSERT_EQ(o.failed.size(), 301u);
    // Every reading's class is the planted one: east failures short, west failures long, the rest ok.
    ASSERT_EQ(o.outcome.size(), run.outcome.size());
    long long same = 0;
    for (size_t j = 0; j < run.outcome.size(); ++j) {
        same += o.outcome[j] == run.outcome[j];
        EXPECT_EQ(bool(o.failed[j / 360][j % 360]), run.outcome[j] != ReadingOutcome::Ok);
    }
    EXPECT_EQ(same, (long long)run.outcome.size());
    EXPECT_GT(o.shorter, 1000);
    EXPECT_GT(o.longer, 1000);
    EXPECT_EQ(o.readings, 301 * 360);
    // Per wall, the scanlines whose ring neighbours see the same wall, by the court's closed form.
    std::map<std::string, std::vector<double>> sight;
    std::map<std::string, size_t> count;
    for (int i = 0; i < 360; ++i) {
        const double b = omniBearing(i);
        const std::string w = courtWallName(b);
        if (courtWallName(omniBearing((i + 359) % 360)) == w && courtWallName(omniBearing((i + 1) % 360)) == w)
            sight[w].push_back(std::hypot(courtWall(b), 0.931));
        EXPECT_NEAR(o.truth_m[size_t(i)], courtWall(b), 2e-3) << "scanline " << i;
        EXPECT_NEAR(o.sight_m[size_t(i)], std::hypot(courtWall(b), 0.931), 2e-3) << "scanline " << i;
    }
    ASSERT_EQ(o.in.groups.size(), 4u);
    for (const BeamGroup& g : o.in.groups) {
        ASSERT_TRUE(sight.count(g.name)) << g.name;
        EXPECT_EQ(g.intervals_rad.size(), sight[g.name].size()) << g.name;
        EXPECT_NEAR(g.range_m, median(sight[g.name]), 2e-3) << g.name;
    }
}

TEST(OmniFit, RecoversEachWallsPlantedThresholdWithErrorsThatAreNotUnderstated)
{
    int within = 0, fits = 0;
    double z2 = 0;
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
            const double z = (th.S_star.value - planted.at(th.group)) / th.S_star.se;
            z2 += z * z;
            within += std::abs(z) < 2;
            EXPECT_LT(std::abs(z), 4) << th.group;
        }
    }
    ASSERT_EQ(fits, 10);
    // Errors neither overstated nor badly understated: most fits within 2 SE, and the pulls' RMS in
    // [0.6, 1.5]. About 1 on these ten; 1.31 over twelve seeds with two beyond 3 SE, somewhat
    // understated for this smooth threshold (the fitted width is taken as known in the bootstrap's
    // draws); the analytic floor the bootstrap replaced gave 0.53, which the lower bound rejects.
    EXPECT_GE(within, 7);
    EXPECT_GT(std::sqrt(z2 / fits), 0.6);
    EXPECT_LT(std::sqrt(z2 / fits), 1.5);
}

TEST(OmniFit, FindsEachWallsOnsetAsOneColumnAlongTheLineOfSight)
{
    // The diagnosis' plant fails a scanline where the column along its line of sight, ρ·√(d² + h²),
    // exceeds P (north wall P·e^−0.7), whatever the saturation: the fit assumes a threshold in S
    // per wall, not that column. Across seeds each wall's P comes back within 3 SE + 8 % (a wall
    // seen over a spread of distances shifts the probit's centre by a few %); with the horizontal
    // distance in place of the line of sight it would be 15–30 % low.
    const CurveFitResult calib = readCalibrationJson("bocas");
    const double P = 0.003;
    for (unsigned seed = 1; seed <= 3; ++seed) {
        const PlantedOmniRun run = plantOmniDiagnosisRun(seed, P, [&](double rho) { return calib.curve(rho); });
        const OmniFitInputs o = loadOmniFitInputs(plantedFiles(run, "column", smokyCourt()), OmniFitConfig{});
        const SensorFitResult r =
            fitSensor(o.in.log, o.in.saturation, o.in.groups, o.spec, &o.in.calibration, SensorFitConfig{}, o.failed);
        ASSERT_TRUE(r.ok()) << "seed " << seed;
        for (const ThresholdFit& th : r.thresholds) {
            // The west wall's smudged scanlines (the plant's 170°–190°) fail in clear air too, which
            // a threshold without a floor cannot take: the diagnosis names that, not the fit.
            if (th.group == "wall_west") continue;
            ASSERT_TRUE(th.fitted) << th.group << " " << th.diagnosis;
            const double want = th.group == "wall_north" ? P * std::exp(-0.7) : P;
            EXPECT_NEAR(th.penetration_power.value, want, 3 * th.penetration_power.se + 0.08 * want)
                << th.group << " seed " << seed;
        }
    }
}

TEST(OmniFit, RefusesMovingCamerasRangedGroupsAndFailureMasksOfAnotherShape)
{
    FitInputsConfig c = plantedFiles(1, "refuse");
    std::string moving = omniCourt();
    moving.replace(moving.find("time_s = 0\n"), 11,
                   "time_s = 0\n[[robots.keyframes]]\ntime_s = 2\nposition = [0.5, 0, 0]\n");
    c.scene = file("court_moving.toml", moving);
    EXPECT_NE(errorOf([&] { loadOmniFitInputs(c, OmniFitConfig{}); }).find("moving camera"), std::string::npos);
    c = plantedFiles(1, "refuse");
    c.surfaces = {"east=-10:10@1.5"};
    EXPECT_NE(errorOf([&] { loadOmniFitInputs(c, OmniFitConfig{}); }).find("gives a range"), std::string::npos);
    c.surfaces = {"east=-10:10"};
    const OmniFitInputs o = loadOmniFitInputs(c, OmniFitConfig{});
    ASSERT_EQ(o.in.groups.size(), 1u);
    EXPECT_NEAR(o.in.groups[0].range_m, std::hypot(1.5, 0.931), 0.01);
    FailureMask wrong = o.failed;
    wrong.pop_back();
    EXPECT_NE(errorOf([&] {
                  fitSensor(o.in.log, o.in.saturation, o.in.groups, o.spec, &o.in.calibration, {}, wrong);
              }).find("failure mask"),
              std::string::npos);
    OmniFitConfig bad;
    bad.tolerance_m = 0;
    EXPECT_NE(errorOf([&] { loadOmniFitInputs(c, bad); }).find("--tolerance"), std::string::npos);
    bad = OmniFitConfig{};
    bad.floor_z_m = 1.0;  // above the camera
    EXPECT_NE(errorOf([&] { loadOmniFitInputs(c, bad); }).find("--floor-z"), std::string::npos);
    bad = OmniFitConfig{};
    bad.max_range_m = 1.0;  // most readings beyond it: the wrong unit or range
    EXPECT_NE(errorOf([&] { loadOmniFitInputs(c, bad); }).find("--unit"), std::string::npos);
    bad.max_range_m = 0.5;  // the tolerance takes half of it
    EXPECT_NE(errorOf([&] { loadOmniFitInputs(c, bad); }).find("below half the maximum range"), std::string::npos);
    bad = OmniFitConfig{};
    bad.floor_z_m = -0.5;  // 1.431 m below the camera, where the court's floor is 0.931 m down
    EXPECT_NE(errorOf([&] { loadOmniFitInputs(c, bad); }).find("straight below it is 0.931 m down"), std::string::npos);
    FitInputsConfig tiny = c;
    tiny.read.unit_m = 1e-5;  // millimetres read as hundredths of one
    EXPECT_NE(errorOf([&] { loadOmniFitInputs(tiny, OmniFitConfig{}); }).find("below 2 cm"), std::string::npos);
    // A laser's layout (half the circle), and the omnicam's log on a robot turned by 90°.
    const std::string half = rewrittenLog(
        [](int i, const std::string& a, const std::string& r) { return i < 180 ? " " + a + " " + r : std::string(); });
    FitInputsConfig laser = c;
    laser.laser = file("half.log", half);
    EXPECT_NE(errorOf([&] { loadOmniFitInputs(laser, OmniFitConfig{}); }).find("evenly spaced all round"),
              std::string::npos);
    std::string turned = omniCourt();
    turned.replace(turned.find("time_s = 0\n"), 11, "time_s = 0\nyaw_deg = 90\n");
    FitInputsConfig other = c;
    other.scene = file("court_turned.toml", turned);
    EXPECT_NE(errorOf([&] { loadOmniFitInputs(other, OmniFitConfig{}); }).find("in its clearest scans"),
              std::string::npos);
    // The same log with its bearings turned by 0.3 rad: wrong on most scanlines in clear air.
    const FitInputsConfig plain = plantedFiles(1, "refuse");
    EXPECT_NE(
        errorOf([&] { loadOmniFitInputs(relogged(plain, 0.3, 1), OmniFitConfig{}); }).find("in its clearest scans"),
        std::string::npos);
    // 3600 scanlines (omnirange allows 36000), bearings written to 6 decimals: the layout holds.
    const OmniFitInputs fine = loadOmniFitInputs(relogged(plain, 0, 10), OmniFitConfig{});
    EXPECT_EQ(fine.spec.n_beams, 3600);
    EXPECT_EQ(fine.in.groups.size(), 4u);
    // A group across the ±180° seam holds all 21 scanlines of 170°–190°.
    FitInputsConfig seam = c;
    seam.surfaces = {"back=170:190"};
    const OmniFitInputs back = loadOmniFitInputs(seam, OmniFitConfig{});
    int in_back = 0;
    for (double a : back.in.log.scans.front().angle_rad) in_back += back.in.groups[0].contains(a);
    EXPECT_EQ(in_back, 21);
    bad = OmniFitConfig{};
    bad.camera = "nope";
    EXPECT_NE(errorOf([&] { loadOmniFitInputs(c, bad); }).find("no omni camera 'nope'"), std::string::npos);
}

TEST(OmniFitCli, WritesTheReferenceWallsOnsetWhichDiagnoseReadsAndScanRefuses)
{
    const CurveFitResult calib = readCalibrationJson("bocas");
    const double P = 0.003;
    const PlantedOmniRun run = plantOmniDiagnosisRun(4, P, [&](double rho) { return calib.curve(rho); });
    const FitInputsConfig c = plantedFiles(run, "cli", smokyCourt());
    const std::string out = file("omni_fit.toml"), report = file("omni_fit_report.json");
    const std::string args = "fit --laser " + c.laser + " --saturation " + c.saturation + " --scene " + c.scene +
        " --sensor-type omnicam --sensor omni --target-prefix wall_ --out " + out;
    const CliRun r = cli(args);
    ASSERT_EQ(r.status, 0) << r.err << r.out;
    EXPECT_NE(r.out.find("omnicam 'omni', viewpoint 0.931 m above the floor"), std::string::npos) << r.out;
    EXPECT_TRUE(std::filesystem::exists(report));
    // The file holds the reference wall's (most scanlines: the south wall) onset: P, not e^−0.7·P.
    const OmniSensorFile f = readOmniSensorFile(out);
    EXPECT_EQ(f.camera, "omni");
    EXPECT_NEAR(f.penetration_power, P, 0.08 * P);
    EXPECT_LT(std::abs(f.extensions.clock_offset_s), 1.0);
    EXPECT_NE(r.out.find("from 'wall_south'"), std::string::npos) << r.out;
    // The chain: a diagnosis from that onset names what the plant put in.
    const std::string diag = (dir() / "omni_fit_diag").string();
    std::filesystem::remove_all(diag);
    const CliRun d = cli("diagnose --laser " + c.laser + " --saturation " + c.saturation + " --scene " + c.scene +
                         " --camera target_camera --sensor-type omnicam --sensor-file " + out + " --out " + diag);
    ASSERT_EQ(d.status, 0) << d.err << d.out;
    for (const char* cause : {"smoke_obstacle_return", "surface_threshold on wall_north", "sector_dropout"})
        EXPECT_NE(d.out.find(cause), std::string::npos) << cause << "\n" << d.out;
    expectBad("scan " + c.scene + " --sensor-file " + out + " --out " + file("never.log"), "omnicam",
              file("never.log"));
    const std::string no = file("never.toml");
    expectBad("fit --laser " + c.laser + " --saturation " + c.saturation +
                  " --sensor-type omnicam --surface e=0:10 --out " + no,
              "needs --scene", no);
    expectBad(args.substr(0, args.find(" --out")) + " --tolerance 0 --out " + no, "--tolerance", no);
    // A log of clear air alone: a few misreadings, never half a wall's, are no onset.
    std::string clear;
    std::istringstream lines(run.log_text);
    std::getline(lines, clear);
    for (std::string line; clear.size() < 20 * line.size() + 1 && std::getline(lines, line);) clear += "\n" + line;
    const std::string clear_log = file("clear.log", clear + "\n");
    expectBad("fit --laser " + clear_log + " --saturation " + c.saturation + " --scene " + c.scene +
                  " --sensor-type omnicam --target-prefix wall_ --out " + no,
              "no onset", no);
    expectBad("fit --laser " + c.laser + " --saturation " + c.saturation +
                  " --sensor-type urg04lx --surface e=0:10 --tolerance 0.5 --out " + no,
              "omnicam", no);
}
