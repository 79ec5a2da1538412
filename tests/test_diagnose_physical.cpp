// The physical model's replay (the URG-04LX's AMCW receiver): a clean run names nothing, the
// gold's planted bias is named on the gold, and the extended sensor file round-trips through
// scan's physical model to `none`.
#include <gtest/gtest.h>

#include <filesystem>

#include "plant.hpp"
#include "smokescan/diagnose/diagnosis.hpp"
#include "smokescan/sensor_config/sensor_file.hpp"

using namespace smokescan;
using namespace smokescan::test;

namespace {

/// A BOCAS run of the URG with the physical model (with `sensor_file`'s extensions).
TrueRun simulatePhysical(uint64_t seed, const std::string& sensor_file = "")
{
    const auto dir = std::filesystem::temp_directory_path() / "smokescan_test_physical";
    std::filesystem::create_directories(dir);
    std::string file = sensor_file;
    if (file.empty()) {  // the scene's URG with the physical model
        file = (dir / "physical.toml").string();
        SensorConfig c = bocasWorld().scene.sensors[size_t(bocasWorld().scene.findSensor("hokuyo"))].config;
        c.model = SensorModel::Physical;
        writeSensorFile(file, c);
    }
    return simulateBocas(seed, 360, 1, 0.01, 0, file);
}

Diagnosed diagnosePhysical(const TrueRun& r, const std::string& sensor_file = "")
{
    return diagnoseWith(r, sensor_file, SensorModel::Physical);
}

}  // namespace

TEST(DiagnosePhysical, CleanRunsNameNothingAndThePlantedGoldBiasIsFound)
{
    if (sanitized()) GTEST_SKIP() << "the physical tables over every beam and scale: Release build";
    const auto dir = std::filesystem::temp_directory_path() / "smokescan_test_physical";
    std::filesystem::create_directories(dir);
    TrueRun r = simulatePhysical(41);
    const Diagnosed clean = diagnosePhysical(r);
    EXPECT_EQ(clean.result.verdict, "none");
    // The physical model's own range noise grows in smoke (the fine phasor's SNR): a replay with
    // the datasheet's noise would name range_noise_growth here; the tables carry the receiver's.
    // The gold reads long: +12 % at the penetration power's column, planted on the readings.
    const double P = bocasWorld().scene.sensors[0].config.paper.penetration_power;
    plant(r, [&](BeamView& v) {
        if (v.surface == "target_gold" && !v.truth.error)
            v.value = std::llround(double(v.value) * (1 + 0.12 * v.column / P));
    });
    const Diagnosed gold = diagnosePhysical(r);
    ASSERT_EQ(gold.result.findings.size(), 1u) << gold.result.verdict;
    const Finding& f = gold.result.findings.front();
    EXPECT_EQ(f.cause, "surface_range_bias");
    EXPECT_EQ(f.target, "target_gold");
    const Estimate b = f.parameters.front().second;
    EXPECT_NEAR(b.value, 0.12 / P, 3 * b.se + 0.05 * 0.12 / P);

    // Round trip: the extended file, rescanned by the physical model under another seed, and
    // diagnosed with it: none; diagnosed without it: the bias again.
    SensorConfig extended = gold.replay.config;
    extended.extensions = gold.result.model;
    const std::string file = (dir / "extended.toml").string();
    writeSensorFile(file, extended);
    const TrueRun again = simulatePhysical(42, file);
    EXPECT_EQ(diagnosePhysical(again, file).result.verdict, "none");
    const Diagnosed plain = diagnosePhysical(again);
    ASSERT_EQ(plain.result.findings.size(), 1u) << plain.result.verdict;
    const Estimate b2 = plain.result.findings.front().parameters.front().second;
    EXPECT_NEAR(b2.value, b.value, 3 * std::hypot(b.se, b2.se));
    std::filesystem::remove_all(dir);
}
