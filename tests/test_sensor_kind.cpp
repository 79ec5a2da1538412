// The laser kinds (sensor_config/laser_kind.hpp): one per SensorType, each owning its name, its
// error values and its own keys, checked against the datasheets' numbers written here by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "smokescan/core/error.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/sensor_config/laser_kind.hpp"
#include "smokescan/sensor_config/lms200.hpp"
#include "smokescan/sensor_config/sensor_config.hpp"
#include "smokescan/sensor_config/urg04lx.hpp"
#include "smokescan/sensors/beam_model.hpp"
#include "smokescan/sensors/beam_result.hpp"

using namespace smokescan;

TEST(SensorKind, EachTypeHasOneKindWhoseNameParsesBackToIt)
{
    const std::pair<SensorType, const char*> kinds[] = {{SensorType::Urg04lx, "urg04lx"},
                                                        {SensorType::Lms200, "lms200"}};
    for (const auto& [type, name] : kinds) {
        const LaserKind& k = laserKind(type);
        EXPECT_EQ(k.type(), type);
        EXPECT_STREQ(k.name(), name);
        EXPECT_EQ(findLaserKind(name), &k);
        EXPECT_EQ(parseSensorType(name), type);
        EXPECT_NE(std::string(sensorTypeNames()).find(name), std::string::npos);
        EXPECT_EQ(specFor(SensorConfig::defaults(type)).type, type);
    }
    EXPECT_EQ(laserKind(SensorType::Urg04lx).withArticle(), "an urg04lx");
    EXPECT_EQ(laserKind(SensorType::Lms200).withArticle(), "an lms200");
    EXPECT_EQ(std::string(sensorTypeNames()), "urg04lx or lms200");
    // A rangefinder's first and last lines of rep117: nothing in range, a failed measurement.
    EXPECT_TRUE(std::isinf(laserKind(SensorType::Urg04lx).rep117(0)));
    EXPECT_TRUE(std::isnan(laserKind(SensorType::Urg04lx).rep117(8)));
    EXPECT_TRUE(std::isinf(laserKind(SensorType::Lms200).rep117(8183)));
    EXPECT_TRUE(std::isnan(laserKind(SensorType::Lms200).rep117(8191)));
    EXPECT_EQ(findLaserKind("omnicam"), nullptr);
    EXPECT_EQ(findLaserKind("URG04LX"), nullptr);
    EXPECT_FALSE(parseSensorType(""));
}

TEST(SensorKind, ErrorValuesAreEachDatasheetsCodes)
{
    // URG-04LX, SCIP 2.0: 0…19 are error codes, 20 mm is the first range.
    const LrfSpec urg = urg04lx();
    for (long long v : {0LL, 1LL, 8LL, 18LL, 19LL}) EXPECT_TRUE(urg.isErrorValue(v)) << v;
    for (long long v : {20LL, 1000LL, 5600LL, 5601LL}) EXPECT_FALSE(urg.isErrorValue(v)) << v;
    EXPECT_TRUE(std::isnan(urg.rangeOf(8)));
    EXPECT_FALSE(urg.isErrorValue(std::llround(urg.range_min_m / urg.unit_m)));
    EXPECT_TRUE(urg.isErrorRange(0.0194));
    EXPECT_FALSE(urg.isErrorRange(0.0196));
    EXPECT_NE(urg.errorValueSummary().find("below 20"), std::string::npos);
    EXPECT_DOUBLE_EQ(urg.rangeOf(1234), 1.234);
    // LMS200: 8183 (no echo), 8189 (weak or ambiguous), 8191 (dazzled); 0…8182 are ranges.
    for (double mode : {8.0, 80.0}) {
        const LrfSpec lms = lms200(0.5, mode);
        for (long long v : {8183LL, 8189LL, 8191LL}) EXPECT_TRUE(lms.isErrorValue(v)) << v;
        for (long long v : {0LL, 1LL, 8182LL}) EXPECT_FALSE(lms.isErrorValue(v)) << v;
        EXPECT_TRUE(lms.isErrorValue(-1));
        // A logged range is an error value where it rounds onto one in the mode's unit.
        const double unit = mode == 8.0 ? 0.001 : 0.01;
        EXPECT_TRUE(lms.isErrorRange(8182.5 * unit));
        EXPECT_FALSE(lms.isErrorRange(8182.4 * unit));
        // Readings are raised to range_min_m, which must itself be a range value.
        EXPECT_FALSE(lms.isErrorValue(std::llround(lms.range_min_m / lms.unit_m)));
        EXPECT_NE(lms.errorValueSummary().find("8183"), std::string::npos);
        EXPECT_DOUBLE_EQ(lms.rangeOf(8182), 8182 * (mode == 8.0 ? 0.001 : 0.01));
    }
    EXPECT_EQ(lms200(1.0).n_beams, 181);
    EXPECT_EQ(lms200(0.5).n_beams, 361);
    EXPECT_EQ(urg.n_beams, 682);
}

TEST(SensorKind, AReadingIsAnErrorValueOnlyWhereItRoundsOntoOne)
{
    // The LMS200 (mm mode, σ 5 mm): readings round onto 8183 (no echo) above 8182.5 mm, so a true
    // range at its maximum 8182 mm errs with P(z > 0.1) = 46.02 %, one σ below the edge 15.87 %;
    // the URG-04LX's values have no upper edge.
    const LrfSpec lms = lms200(0.5, 8.0);
    EXPECT_NEAR(reportErrorProbability(lms, 8.182), 0.460172, 1e-5);
    EXPECT_NEAR(reportErrorProbability(lms, 8.1825 - 0.005), 0.158655, 1e-5);
    EXPECT_LT(reportErrorProbability(lms, 8.0), 1e-100);
    EXPECT_EQ(reportErrorProbability(lms, 8.19), 1.0);  // beyond range_max_m
    const LrfSpec urg = urg04lx();
    EXPECT_EQ(reportErrorProbability(urg, 5.6), 0.0);
    EXPECT_EQ(reportErrorProbability(urg, 0.02), 0.0);
    EXPECT_EQ(reportErrorProbability(urg, 0.019), 1.0);
}

TEST(SensorKind, EachKindsModelsAndWhatCanBeFittedForItAreAskedOfIt)
{
    const LaserKind& urg = laserKind(SensorType::Urg04lx);
    const LaserKind& lms = laserKind(SensorType::Lms200);
    EXPECT_EQ(urg.receiver(), Receiver::Amcw);
    EXPECT_EQ(lms.receiver(), Receiver::Pulsed);
    EXPECT_TRUE(urg.learnsExtensions() && urg.fitsPhysicalModel() && !urg.fitsPlume());
    EXPECT_TRUE(!lms.learnsExtensions() && !lms.fitsPhysicalModel() && lms.fitsPlume());
    // The defaults are each kind's calibration (docs/sensors.md).
    EXPECT_EQ(urg.physicalDefaults().noise_floor, 1.728e-4);
    EXPECT_EQ(lms.physicalDefaults().divergence_mrad, 12.0);
    for (SensorType t : {SensorType::Urg04lx, SensorType::Lms200})
        for (SensorModel m : {SensorModel::Paper, SensorModel::Physical}) {
            SensorConfig c = SensorConfig::defaults(t);
            c.model = m;
            const auto model = makeBeamModel(c);
            ASSERT_TRUE(model);
            EXPECT_EQ(model->spec().type, t);
            // The paper model's smoke parameter is its penetration power, the physical model's
            // its receiver's noise floor.
            EXPECT_EQ(model->smokeParameter().rfind(m == SensorModel::Paper ? "penetration_power=" : "noise_floor=", 0),
                      0u)
                << model->smokeParameter();
        }
    // A learned extension on a kind whose models take none is refused, naming the kind.
    SensorConfig c = SensorConfig::defaults(SensorType::Lms200);
    c.extensions.smoke_obstacle_return = 0.5;
    try {
        (void)makeBeamModel(c);
        FAIL() << "an lms200 with extensions was made";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("an lms200's models take none"), std::string::npos) << e.what();
    }
}

TEST(SensorKind, ASceneSensorTakesItsOwnKindsKeysAndRefusesAnothers)
{
    const Scene s = parseScene(
        "[[sensors]]\ntype = \"lms200\"\nresolution_deg = 1.0\nrange_mode_m = 80.0\n"
        "[sensors.physical]\npulse_fwhm_ns = 4.0\n",
        "lms.toml", ".");
    ASSERT_EQ(s.sensors.size(), 1u);
    const LrfSpec spec = specFor(s.sensors[0].config);
    EXPECT_EQ(spec.n_beams, 181);
    EXPECT_DOUBLE_EQ(spec.unit_m, 0.01);
    EXPECT_EQ(s.sensors[0].config.physical.pulse_fwhm_ns, 4.0);
    auto refused = [](const std::string& text) {
        try {
            (void)parseScene(text, "bad.toml", ".");
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_NE(refused("[[sensors]]\ntype = \"lms200\"\n[sensors.physical]\nmod_freq_lo_hz = 1e7\n")
                  .find("not a key of the physical model of an lms200"),
              std::string::npos);
    EXPECT_NE(refused("[[sensors]]\ntype = \"urg04lx\"\nrange_mode_m = 80.0\n").find("not a key of an urg04lx sensor"),
              std::string::npos);
    EXPECT_NE(refused("[[sensors]]\ntype = \"lms200\"\nresolution_deg = 0.25\n").find("resolution_deg"),
              std::string::npos);
}
