// The loop closed: a diagnosis' extended sensor file, rescanned by `smokescan scan`, simulates
// what was found (a diagnosis of the rescanned run with the plain model finds it again, at the
// same magnitude), and the rescanned run diagnosed with that file names nothing more.
#include <gtest/gtest.h>

#include <filesystem>

#include "plant.hpp"
#include "smokescan/diagnose/diagnosis.hpp"
#include "smokescan/sensor_config/sensor_file.hpp"

using namespace smokescan;
using namespace smokescan::test;

namespace {

const Finding* findingOf(const DiagnosisResult& d, const std::string& cause, const std::string& target)
{
    for (const auto& f : d.findings)
        if (f.cause == cause && f.target == target) return &f;
    return nullptr;
}

}  // namespace

TEST(DiagnoseRoundTrip, RescannedExtendedRunDiagnosesAsNone)
{
    if (sanitized()) GTEST_SKIP() << "three diagnoses and two scans: the Release build (the paths run in the others)";
    const auto dir = std::filesystem::temp_directory_path() / "smokescan_test_roundtrip";
    std::filesystem::create_directories(dir);
    // The gold reads long as smoke thickens (β = 14 per density·m), planted through the readings;
    // a dirty window fails 45 % of the beams from −50° to −35°.
    TrueRun r = simulateBocas(31);
    KeyedRng rng(31, 99);
    plant(r, [&](BeamView& v) {
        if (v.surface == "target_gold" && !v.truth.error) v.value = std::llround(double(v.value) * (1 + 14 * v.column));
        const double deg = v.angle_rad * 180 / M_PI;
        if (deg >= -50 && deg <= -35 && v.truth.hit.hit && rng.uniform() < 0.45) v.value = 0;
    });
    const Diagnosed first = diagnoseWith(r);
    const Finding* bias = findingOf(first.result, "surface_range_bias", "target_gold");
    ASSERT_NE(bias, nullptr) << first.result.verdict;
    ASSERT_EQ(first.result.findings.size(), 2u) << first.result.verdict;

    // The extended sensor file, as `smokescan diagnose` writes it.
    SensorConfig extended = first.replay.config;
    extended.extensions = first.result.model;
    const std::string file = (dir / "sensor.toml").string();
    writeSensorFile(file, extended, "round trip");
    ASSERT_EQ(extended.extensions.surfaces.count("target_gold"), 1u);
    ASSERT_EQ(extended.extensions.sectors.size(), 1u);

    // Rescanned with the file (another seed): the scan simulates both effects ...
    const TrueRun again = simulateBocas(32, 360, 1, 0.01, 0, file);
    const Diagnosed plain = diagnoseWith(again);
    const Finding* bias2 = findingOf(plain.result, "surface_range_bias", "target_gold");
    ASSERT_NE(bias2, nullptr) << plain.result.verdict;
    const Estimate b1 = bias->parameters.front().second, b2 = bias2->parameters.front().second;
    EXPECT_NEAR(b2.value, b1.value, 3 * std::hypot(b1.se, b2.se)) << "the rescan's bias against the file's";
    // The dirty window's dropout, as the file has it and as the rescan shows it.
    const Finding* sector = nullptr;
    for (const auto& f : plain.result.findings)
        if (f.cause == "sector_dropout") sector = &f;
    ASSERT_NE(sector, nullptr) << plain.result.verdict;
    const double d_file = extended.extensions.sectors.front().dropout;
    const Estimate d2 = sector->parameters.front().second;
    EXPECT_NEAR(d_file, 0.45, 0.05) << "the first diagnosis' dropout";
    EXPECT_NEAR(d2.value, d_file, 3 * d2.se + 0.03) << "the rescan's dropout against the file's";
    // ... and diagnosed with the file, nothing more is named.
    const Diagnosed closed = diagnoseWith(again, file);
    EXPECT_EQ(closed.result.verdict, "none");
    EXPECT_GT(closed.result.baseline.front().loglik_per_beam, plain.result.baseline.front().loglik_per_beam);
    std::filesystem::remove_all(dir);
}
