// `smokescan diagnose` on the omnicam's log: a planted run whose smoke-stopped scanlines read short
// (not the "no return" today's model expects), whose north wall fails at half the onset and whose
// mirror is smudged over 20° (readings at the maximum range); the diagnosis must name all three,
// and the CLI writes the omnicam's extended sensor file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "cli_run.hpp"
#include "omni_fit_run.hpp"
#include "smokescan/calib/calibration.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/diagnose/diagnosis.hpp"
#include "smokescan/fit/omni_fit.hpp"
#include "smokescan/sensor_config/sensor_file.hpp"

using namespace smokescan;
using namespace smokescan::test;

namespace {

constexpr double kP = 0.003;  ///< the omnicam's onset in the planted run and its sensor file [density·m]
constexpr double kH = 0.931;  ///< the court's viewpoint above the floor [m]

/// The planted run's files (the robot turned by yaw_deg): log, saturation, scene, the omnicam's
/// sensor file (onset kP).
FitInputsConfig plantedDiagnosisFiles(unsigned seed, double yaw_deg, const std::string& tag)
{
    const CurveFitResult calib = readCalibrationJson("bocas");
    const PlantedOmniRun run = plantOmniDiagnosisRun(
        seed, kP, [&](double rho) { return calib.curve(rho); }, yaw_deg);
    FitInputsConfig c;
    c.laser = file("diag_" + tag + ".log", run.log_text);
    c.saturation = file("diag_" + tag + ".csv", run.saturation_text);
    c.scene = file("smoky_court_" + tag + ".toml", smokyCourt(yaw_deg));
    OmniSensorFile f;
    f.camera = "omni";
    f.penetration_power = kP;
    writeOmniSensorFile(file("omni_onset.toml"), f, "planted");
    return c;
}

Replay plantedReplay(const FitInputsConfig& c, double max_range_m = 3.8)
{
    OmniFitConfig oc;
    oc.groups = false;
    oc.max_range_m = max_range_m;
    const OmniFitInputs o = loadOmniFitInputs(c, oc);
    ReplayConfig rc;
    rc.camera = "target_camera";
    return replayOmniRun(o, readOmniSensorFile(file("omni_onset.toml")), rc);
}

const Finding* omniFindingOf(const DiagnosisResult& r, const std::string& cause)
{
    for (const Finding& f : r.findings)
        if (f.cause == cause) return &f;
    return nullptr;
}

/// The three planted findings, and nothing else; the smudge's sector in the replay's bearings
/// [deg] (from the first scanline on, so that it may cross ±180°).
void expectPlanted(const DiagnosisResult& r, double sector_from_deg, double sector_to_deg)
{
    const Finding* q = omniFindingOf(r, "smoke_obstacle_return");
    ASSERT_NE(q, nullptr) << r.verdict;
    EXPECT_GT(q->parameters.at(0).second.value, 0.95) << r.verdict;
    const Finding* north = omniFindingOf(r, "surface_threshold");
    ASSERT_NE(north, nullptr) << r.verdict;
    EXPECT_EQ(north->target, "wall_north");
    const Estimate theta = north->parameters.at(0).second;
    EXPECT_NEAR(theta.value, -0.7, 4 * theta.se + 0.01) << theta.se;
    const Finding* smudge = omniFindingOf(r, "sector_dropout");
    ASSERT_NE(smudge, nullptr) << r.verdict;
    EXPECT_NEAR(smudge->parameters.at(0).second.value, 0.5, 0.05);
    ASSERT_EQ(r.model.sectors.size(), 1u);
    EXPECT_NEAR(r.model.sectors[0].from_deg, sector_from_deg, 2.0);
    EXPECT_NEAR(r.model.sectors[0].to_deg, sector_to_deg, 2.0);
    std::string tried;
    for (const auto& t : r.tried)
        tried += "\n  round " + std::to_string(t.round) + " " + t.cause + " " + t.target + " gain " +
            std::to_string(t.loglik_gain) + " p " + std::to_string(t.p_value) + " effect " + std::to_string(t.effect) +
            " ± " + std::to_string(t.effect_se) + " floor " + std::to_string(t.floor);
    EXPECT_EQ(r.findings.size(), 3u) << r.verdict << tried;
    EXPECT_GT(r.extended.front().loglik_per_beam, r.baseline.front().loglik_per_beam + 0.5);
}

}  // namespace

TEST(OmniDiagnosis, NamesShortReadingsInSmokeTheWallThatFailsEarlyAndASmudgeAcrossTheBearingsSeam)
{
    const Replay replay = plantedReplay(plantedDiagnosisFiles(7, 0, "seam"));
    ASSERT_EQ(replay.beams.size(), 360u);
    // A clear reading's noise is one pixel's metric error where the wall meets the floor: the
    // court camera's floor distances half a pixel out and in, apart.
    const OmniCamera cam = courtCamera();
    for (size_t b = 0; b < 360; ++b) {
        const double d = courtWall(omniBearing(int(b)));
        const double rho = cam.radius(std::atan(d / kH));
        const double pixel = cam.floorDistance(rho + 0.5, kH) - cam.floorDistance(rho - 0.5, kH);
        EXPECT_NEAR(replay.beams[b].sigma_m, pixel, 0.03 * pixel) << "scanline " << b;
    }
    // The smudge at 170°–190° spans the log's ±180° seam; the replay's bearings run on from 0°.
    expectPlanted(diagnose(replay), 169.5, 190.5);
}

TEST(OmniDiagnosis, LooksThroughEachLineOfSightOfATurnedRobot)
{
    const FitInputsConfig c = plantedDiagnosisFiles(11, 30, "turned");
    const Replay replay = plantedReplay(c);
    // At the densest scan the column along each scanline is the density times its line of sight
    // to the wall the turned robot faces at that bearing (world bearing = scanline's + 30°).
    size_t k = 0;
    for (size_t j = 0; j < replay.scans.size(); ++j)
        if (replay.scans[j].density > replay.scans[k].density) k = j;
    ASSERT_GT(replay.scans[k].density, 0.003);
    for (size_t b = 0; b < 360; ++b) {
        const double sight = std::hypot(courtWall(omniBearing(int(b)) + M_PI / 6), kH);
        EXPECT_NEAR(replay.columnAt(k, b) / replay.scans[k].density, sight, 0.01 * sight) << "scanline " << b;
    }
    // The smudge at world 170°–190° is at the camera's 140°–160°.
    expectPlanted(diagnose(replay), 139.5, 160.5);
    // Scanlines whose wall lies beyond the maximum range are left out, as a laser's no return.
    const Replay near = plantedReplay(c, 2.6);
    for (size_t b = 0; b < 360; ++b)
        EXPECT_EQ(near.beams[b].surface < 0, courtWall(omniBearing(int(b)) + M_PI / 6) >= 2.6) << "scanline " << b;
}

TEST(OmniDiagnosisCli, WritesTheOmnicamsExtendedFileAndRefusesWhatItCannotReplay)
{
    const FitInputsConfig c = plantedDiagnosisFiles(8, 0, "cli");
    const std::string onset = file("omni_onset.toml"), out = (dir() / "omni_diag").string();
    const std::string base = "diagnose --laser " + c.laser + " --saturation " + c.saturation + " --scene " + c.scene +
        " --camera target_camera --sensor-type omnicam";
    std::filesystem::remove_all(out);
    const CliRun r = cli(base + " --sensor-file " + onset + " --out " + out);
    ASSERT_EQ(r.status, 0) << r.err << r.out;
    EXPECT_NE(r.out.find("smoke_obstacle_return"), std::string::npos) << r.out;
    const OmniSensorFile learned = readOmniSensorFile(out + "/sensor.toml");
    EXPECT_GT(learned.extensions.smoke_obstacle_return, 0.95);
    ASSERT_TRUE(learned.extensions.surfaces.count("wall_north"));
    EXPECT_NEAR(learned.extensions.surfaces.at("wall_north").threshold_factor, -0.7, 0.15);
    ASSERT_EQ(learned.extensions.sectors.size(), 1u);
    EXPECT_NEAR(learned.extensions.sectors[0].from_deg, 169.5, 2.0);
    EXPECT_DOUBLE_EQ(learned.penetration_power, kP);
    const std::string no = (dir() / "omni_diag_never").string();
    expectBad(base + " --out " + no, "needs --sensor-file", no);
    const std::string laser_file = file("urg_file.toml", "type = \"urg04lx\"\n[paper]\npenetration_power = 0.007\n");
    expectBad(base + " --sensor-file " + laser_file + " --out " + no, "omnicam", no);
    const std::string extra =
        file("omni_extra.toml", "type = \"omnicam\"\n[paper]\npenetration_power = 0.003\nlocal_threshold = 0.002\n");
    expectBad(base + " --sensor-file " + extra + " --out " + no, "local_threshold", no);
    const std::string none = file("omni_none.toml", "type = \"omnicam\"\n[paper]\n");
    expectBad(base + " --sensor-file " + none + " --out " + no, "penetration_power", no);
    expectBad(base + " --sensor-file " + onset + " --model paper --out " + no, "--model", no);
    expectBad(base + " --sensor-file " + onset + " --sensor target_camera --out " + no, "is the onset of 'omni'", no);
    expectBad(base + " --sensor-file " + onset + " --tolerance 0.5 --out " + no, "was fitted with 0.3", no);
    // The option the onset was fitted with is accepted.
    const std::string same = (dir() / "omni_diag_same").string();
    std::filesystem::remove_all(same);
    EXPECT_EQ(cli(base + " --sensor-file " + onset + " --tolerance 0.3 --out " + same).status, 0);
    expectBad("diagnose --laser " + c.laser + " --saturation " + c.saturation + " --scene " + c.scene +
                  " --camera target_camera --tolerance 0.5 --out " + no,
              "omnicam", no);
}
