// `smokescan omnirange`: a run on a rendered court, its outputs, and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "cli_run.hpp"
#include "omni_court.hpp"
#include "smokescan/io/recorded.hpp"

using namespace smokescan;
using namespace smokescan::test;

TEST(OmnirangeCli, ReadsTheCourtWritesLogsAndReusesItsHistogram)
{
    const std::string scene = file("court.toml", omniCourt());
    const std::string out = file("omni.log"), laser = file("laser.log"), hist = file("hist.txt");
    const CliRun r = cli("omnirange " + scene + " --train 0 --from 0 --to 1 --spp 16 --out " + out + " --laser-out " +
                         laser + " --save-histogram " + hist);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("omnicam against the laser"), std::string::npos) << r.out;
    const RecordedLog log = readRecordedLog(out);
    ASSERT_EQ(log.scans.size(), 2u);
    ASSERT_EQ(log.scans[0].range.size(), 360u);
    // Straight ahead the wall 1.5 m away, to the left 2.0 m, behind 2.5 m, to the right 1.2 m.
    const double want[4] = {1.5, 2.0, 2.5, 1.2};
    // (R = 75 px: one pixel is 0.1 m at 1.5–2 m and 0.15 m at 2.5 m; the tolerance is 12 %.)
    for (int q = 0; q < 4; ++q)
        EXPECT_NEAR(log.scans[0].range[size_t(90 * q)] / 1000, want[q], 0.12 * want[q]) << "quadrant " << q;
    const RecordedLog ll = readRecordedLog(laser);
    ASSERT_EQ(ll.scans.size(), 2u);
    ASSERT_EQ(ll.scans[0].range.size(), 361u);  // the LMS200 at 0.5°, as it reports them
    EXPECT_NEAR(ll.scans[0].range[180] / 1000, 1.5, 0.03);  // straight ahead: the wall
    // The saved histogram reads the same frames the same way.
    const std::string again = file("again.log");
    const CliRun r2 = cli("omnirange " + scene + " --histogram " + hist + " --from 0 --to 1 --spp 16 --out " + again);
    ASSERT_EQ(r2.status, 0) << r2.err;
    const RecordedLog log2 = readRecordedLog(again);
    ASSERT_EQ(log2.scans.size(), 2u);
    for (size_t k = 0; k < 2; ++k) EXPECT_EQ(log2.scans[k].range, log.scans[k].range) << "scan " << k;
}

TEST(OmnirangeCli, TruthComparesEverySensorByTheSmokeColumnItsLineOfSightCrosses)
{
    // The court filled with uniform smoke of density 0.0005: the omnicam's lines of sight (1.5–3.3
    // m long) and the Sick's beams (1.2–2.5 m) cross 0.0006–0.0017 density·m.
    const std::string scene = file("smoky_court.toml", omniCourt() + R"(
[[smoke]]
name = "haze"
type = "box"
min = [-4.0, -4.0, -1.0]
max = [4.0, 4.0, 3.0]
density = 0.0005
voxel = 0.1
)");
    const std::string out = file("smoky.log"), fig = file("versus.png");
    const CliRun r = cli("omnirange " + scene + " --train 0 --from 0 --to 0 --spp 4 --out " + out + " --truth " + fig);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(std::filesystem::exists(fig));
    // Each sensor's readings per bin against the court's geometry: the column is 0.0005 × the
    // line of sight (the omnicam's slant view down to the wall's foot from 0.931 m, the Sick's
    // horizontal beam), the upper bin from 2 m of it. Lines of sight within a centimetre of 2 m
    // (float hits) may fall either side.
    long long omni_lo = 0, omni_hi = 0, sick_lo = 0, sick_hi = 0, either = 0;
    for (int i = 0; i < 360; ++i) {
        const double len = std::hypot(courtWall(2 * M_PI * i / 360), 0.931);
        (std::abs(len - 2) < 0.01 ? either : len < 2 ? omni_lo : omni_hi)++;
    }
    for (int i = 0; i <= 360; ++i) {
        const double len = courtWall(-M_PI / 2 + M_PI * i / 360);
        (std::abs(len - 2) < 0.01 ? either : len < 2 ? sick_lo : sick_hi)++;
    }
    const auto readings = [&](const std::string& sensor, const std::string& bin) {
        const size_t at = r.out.find(sensor + " (max range"), end = r.out.find("  all ", at);
        const size_t line = r.out.find("  " + bin + " ", at);
        if (at == std::string::npos || line == std::string::npos || line > end) return 0LL;
        return std::stoll(r.out.substr(line + bin.size() + 2));
    };
    EXPECT_NEAR(double(readings("omnicam", "0.0003-0.001")), double(omni_lo), double(either)) << r.out;
    EXPECT_NEAR(double(readings("omnicam", "0.001-0.003")), double(omni_hi), double(either)) << r.out;
    EXPECT_EQ(readings("omnicam", "0.0003-0.001") + readings("omnicam", "0.001-0.003"), 360) << r.out;
    EXPECT_NEAR(double(readings("sick", "0.0003-0.001")), double(sick_lo), double(either)) << r.out;
    EXPECT_NEAR(double(readings("sick", "0.001-0.003")), double(sick_hi), double(either)) << r.out;
    EXPECT_EQ(readings("sick", "0.0003-0.001") + readings("sick", "0.001-0.003"), 361) << r.out;
    EXPECT_GT(omni_lo, 30);  // both bins hold many of each
    EXPECT_GT(omni_hi, 30);
    EXPECT_GT(sick_lo, 30);
    EXPECT_GT(sick_hi, 30);
    expectBad("omnirange " + scene + " --train 0 --from 0 --to 0 --spp 1 --out " + file("never2.log") + " --truth " +
                  file("versus.bmp"),
              "unknown image format", file("never2.log"));
}

TEST(OmnirangeCli, BadInputGivesOneLineAndNoOutput)
{
    const std::string scene = file("court.toml", omniCourt());
    const std::string out = file("never_omni.log");
    const std::string base = "omnirange " + scene + " --from 0 --to 0 --spp 1 ";
    expectBad(base + "--train 0 --threshold 0 --out " + out, "threshold", out);
    expectBad(base + "--train 0 --threshold 1.5 --out " + out, "threshold", out);
    expectBad(base + "--train 0 --n-behind 0 --out " + out, "--n-behind", out);
    expectBad(base + "--train 0 --k-free 0 --out " + out, "--k-free", out);
    expectBad(base + "--train 0 --max-range 1e300 --out " + out, "--max-range", out);
    expectBad(base + "--train 0 --exposure 1e300 --out " + out, "--exposure", out);
    expectBad(base + "--train 0 --exposure 1e-9 --out " + out, "--exposure", out);
    expectBad(base + "--train 0 --outlier 0.001 --out " + out, "--outlier", out);
    expectBad(base + "--train 0 --floor-z -200 --out " + out, "--floor-z: puts the floor over 100 m", out);
    expectBad(base + "--train 100 --out " + out, "--train: time 100", out);
    expectBad("omnirange " + scene + " --from 1 --to 5 --spp 1 --train 0 --out " + out,
              "--to: 5 s is after the scene's end, 2 s", out);
    expectBad(base + "--train 0 --floor-z 0.5 --out " + out, "--floor-z", out);
    // A file the scene reads (a sensor file) is an input: never an output.
    const std::string sens = file("court_sick.toml", "type = \"lms200\"\n");
    std::string with_file = omniCourt();
    with_file.replace(with_file.find("robot = \"r\"\nposition = [0, 0, 0.3]"), 0, "sensor_file = \"" + sens + "\"\n");
    const std::string scene2 = file("court2.toml", with_file);
    expectBad("omnirange " + scene2 + " --from 0 --to 0 --spp 1 --train 0 --out " + sens, "a file the scene reads",
              sens + ".never");
    EXPECT_EQ(slurp(sens), "type = \"lms200\"\n");
    // A tilted omni camera: the distance formula takes the mirror's axis as vertical.
    std::string tilted = omniCourt();
    tilted.replace(tilted.find("position = [0, 0, 0.931]"), 24, "position = [0, 0, 0.931]\nrpy_deg = [0, 20, 0]");
    const std::string tilt = file("tilted.toml", tilted);
    expectBad("omnirange " + tilt + " --from 0 --to 0 --spp 1 --train 0 --out " + out, "must look straight down", out);
    expectBad(base + "--out " + out, "give either --train TIMES or --histogram FILE", out);
    const std::string junk = file("junk_hist.txt", "# smokescan colour histogram v1, bins per channel: 13\n1 2 x 4\n");
    expectBad(base + "--histogram " + junk + " --out " + out, junk + ":2: expected 'r g b count'", out);
    expectBad(base + "--train 0 --out " + scene, "the scene", scene + ".never");
    const std::string big = file("big_mirror.toml",
                                 omniCourt("base_radius_px = 0\n")
                                     .replace(omniCourt().find("mirror_radius_px = 75"), 21, "mirror_radius_px = 400"));
    expectBad("omnirange " + big + " --train 0 --out " + out, "outside the image or the mirror's rim", out);
    const std::string no_omni = file("no_omni.toml", "[[sensors]]\ntype = \"lms200\"\n");
    expectBad("omnirange " + no_omni + " --train 0 --out " + out, "has no omni camera", out);
    // The laser sees no free floor (it looks at the sky): an empty training set.
    std::string blind = omniCourt();
    blind.replace(blind.find("rpy_deg = [0, 0, -90]"), 21, "rpy_deg = [90, 0, -90]");
    const std::string sky = file("blind.toml", blind);
    expectBad("omnirange " + sky + " --from 0 --to 0 --spp 1 --train 0 --out " + out, "no free floor pixels", out);
}
