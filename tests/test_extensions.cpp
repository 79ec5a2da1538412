// The learned extensions (sensors/extensions.hpp) as `smokescan scan` simulates them: the readings'
// statistics against each extension's own closed form, and the sensor file's [extensions] section.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "room_rig.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/quadrature.hpp"
#include "smokescan/core/random.hpp"
#include "smokescan/sensor_config/sensor_file.hpp"
#include "smokescan/sensors/beam_model.hpp"
#include "smokescan/sensors/scanner.hpp"

using namespace smokescan;
using smokescan::test::Rig;
using smokescan::test::roomScene;

namespace {

double Phi(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

/// The URG's paper model in the room with `e`, its straight-ahead beam (angle 0, target at 2.5 m).
struct ExtendedRoom {
    Rig rig{roomScene(1.0, "gold_paper")};  // density 1, scaled by the time line
    SensorConfig cfg;
    std::unique_ptr<BeamModel> model;
    Ray ray;

    explicit ExtendedRoom(const ModelExtensions& e)
    {
        cfg = rig.scene.sensors[size_t(rig.scene.findSensor("hokuyo"))].config;
        cfg.model = SensorModel::Paper;
        cfg.extensions = e;
        model = makeBeamModel(cfg);
        ray = rig.scene.sensors[size_t(rig.scene.findSensor("hokuyo"))].beamRay(0.0);
    }
    /// `n` readings at homogeneous density rho; `rising` the smoke's trend.
    std::vector<BeamResult> read(double rho, bool rising, int n, uint64_t seed = 5)
    {
        rig.scene.volumes[0].timeline = DensityTimeline::constant(rho);
        const SmokeField field = SmokeField::at(rig.scene.volumes, 0.0);
        const BeamWorld w{rig.scene, rig.surfaces, field, rising};
        std::vector<BeamResult> out;
        for (int k = 0; k < n; ++k) {
            KeyedRng rng(seed, uint64_t(k));
            out.push_back(model->read(w, LaserBeam(ray, 0.0), rng, false));
        }
        p_error = model->errorProbability(w, LaserBeam(ray, 0.0));
        return out;
    }
    double p_error = 0;
};

}  // namespace

TEST(Extensions, OnsetWidthDropoutAndShortReturnsHaveTheirProbabilities)
{
    // Width w = 0.25: a beam is stopped with probability Φ((ln C − ln P)/w); a dropout sector over
    // the beam fails 20 % of beams; 40 % of the stopped ones read short, uniform on (0, L).
    ModelExtensions e;
    e.threshold_width = 0.25;
    e.smoke_obstacle_return = 0.4;
    e.sectors.push_back({-5, 5, 0.2});
    ExtendedRoom room(e);
    const double P = room.cfg.paper.penetration_power, L = 2.5;
    const int n = 4000;
    for (double c_over_p : {0.6, 0.9, 1.0, 1.15, 1.6}) {
        const auto rs = room.read(c_over_p * P / L, false, n);
        const double C = rs.front().smoke.column_regional;
        ASSERT_NEAR(C, c_over_p * P, 1e-3 * P);
        const double ps = Phi(std::log(C / P) / 0.25);
        const double p_err = 0.2 + 0.8 * ps * 0.6, p_short = 0.8 * ps * 0.4;
        int err = 0, shortr = 0, dropout = 0;
        for (const auto& r : rs) {
            err += r.error;
            dropout += std::string(r.cause) == "sector_dropout";
            shortr += !r.error && double(r.value) * 0.001 < L - 0.1;
        }
        auto tol = [&](double p) { return 4 * std::sqrt(p * (1 - p) / n) + 1e-3; };
        EXPECT_NEAR(double(err) / n, p_err, tol(p_err)) << "C/P " << c_over_p;
        EXPECT_NEAR(double(shortr) / n, p_short, tol(p_short)) << "C/P " << c_over_p;
        EXPECT_NEAR(double(dropout) / n, 0.2, tol(0.2)) << "C/P " << c_over_p;
        EXPECT_NEAR(room.p_error, p_err, 1e-9) << "the model's own probability, C/P " << c_over_p;
    }
}

TEST(Extensions, SectorsAreInDegreesOfTheBeamAngleAndThresholdsPerSurface)
{
    // A sector from 5° to 10° fails every beam in it: a beam at 7.5° (0.13 rad) fails, beams at
    // 0°, 2° and −7.5° do not (all hit the target, 2.5 m ahead and ±0.5 m wide; read as radians
    // the sector would hold none of them).
    ModelExtensions e;
    e.sectors.push_back({5, 10, 1.0});
    e.surfaces["target"].threshold_factor = std::log(1.5);  // the target fails at 1.5 P
    ExtendedRoom room(e);
    const double P = room.cfg.paper.penetration_power;
    room.rig.scene.volumes[0].timeline = DensityTimeline::constant(0.0);
    const SmokeField clear = SmokeField::at(room.rig.scene.volumes, 0.0);
    const BeamWorld w{room.rig.scene, room.rig.surfaces, clear, false};
    const SensorMount& mount = room.rig.scene.sensors[size_t(room.rig.scene.findSensor("hokuyo"))];
    for (const auto& [deg, fails] :
         std::vector<std::pair<double, bool>>{{7.5, true}, {0, false}, {2, false}, {-7.5, false}}) {
        const double a = deg * M_PI / 180;
        EXPECT_NEAR(room.model->errorProbability(w, LaserBeam(mount.beamRay(a), a)), fails ? 1.0 : 0.0, 1e-12) << deg;
        KeyedRng rng(1, 2);
        EXPECT_EQ(room.model->read(w, LaserBeam(mount.beamRay(a), a), rng, false).error, fails) << deg;
    }
    // The target's own threshold: at 1.3 P it still reads, at 1.7 P it fails (each ≥ 7 widths).
    for (const auto& [c_over_p, fails] : std::vector<std::pair<double, bool>>{{1.3, false}, {1.7, true}}) {
        const auto rs = room.read(c_over_p * P / 2.5, false, 50);
        int err = 0;
        for (const auto& r : rs) err += r.error;
        EXPECT_EQ(err, fails ? 50 : 0) << "C/P " << c_over_p;
    }
}

TEST(Extensions, RisingIsTheRegionalTimeLinesTrend)
{
    // The scan's "rising" (hysteresis): smoke ramping up from 10 s to 20 s, a plateau to 40 s, a
    // fall to 50 s.
    Rig rig(roomScene(1.0, "gold_paper"));
    rig.scene.volumes[0].timeline =
        DensityTimeline::keyframes({{0, 0}, {10, 0}, {20, 1}, {40, 1}, {50, 0}}, DensityTimeline::Interp::Linear);
    EXPECT_TRUE(regionalSmokeRising(rig.scene, 15));
    EXPECT_FALSE(regionalSmokeRising(rig.scene, 30));  // steady
    EXPECT_FALSE(regionalSmokeRising(rig.scene, 45));
    EXPECT_FALSE(regionalSmokeRising(rig.scene, 5));  // clear and steady
}

TEST(Extensions, RangeLimitsAreThePlainModels)
{
    // A sector elsewhere changes nothing near the maximum range: a wall at 5.5 m (the URG's
    // limit is 5.6 m) reads as in the plain model, whatever the noise.
    ModelExtensions e;
    e.sectors.push_back({100, 110, 0.5});
    Rig rig(roomScene(0.0, "gold_paper"));
    SensorConfig cfg = rig.scene.sensors[size_t(rig.scene.findSensor("hokuyo"))].config;
    cfg.model = SensorModel::Paper;
    SensorConfig plain_cfg = cfg;
    cfg.extensions = e;
    const auto ext = makeBeamModel(cfg), plain = makeBeamModel(plain_cfg);
    const SmokeField clear = SmokeField::at(rig.scene.volumes, 0.0);
    const BeamWorld w{rig.scene, rig.surfaces, clear, false};
    Ray ray;
    ray.o = Vec3(0.5, 2, 0);  // 5.5 m from the room's far wall at x = 6, clear of the target
    ray.d = Vec3::UnitX();
    int same = 0;
    for (int k = 0; k < 200; ++k) {
        KeyedRng r1(3, uint64_t(k)), r2(3, uint64_t(k));
        const BeamResult a = ext->read(w, LaserBeam(ray, 0.0), r1, false),
                         b = plain->read(w, LaserBeam(ray, 0.0), r2, false);
        same += a.value == b.value && a.error == b.error;
    }
    EXPECT_EQ(same, 200);
    EXPECT_EQ(ext->errorProbability(w, LaserBeam(ray, 0.0)), plain->errorProbability(w, LaserBeam(ray, 0.0)));
}

TEST(Extensions, ThePhysicalModelMovesItsOnsetByScalingTheSmoke)
{
    // The URG's physical model with a threshold factor e^0.4 on the target and a width of 0.3:
    // its error probability at smoke scale s is the plain model's at s·e^−0.4, averaged over
    // e^(0.3 z) (the normal's quantiles), and the share of errors in the draws agrees with it.
    Rig rig(roomScene(1.0, "gold_paper"));
    SensorConfig cfg = rig.scene.sensors[size_t(rig.scene.findSensor("hokuyo"))].config;
    cfg.model = SensorModel::Physical;
    SensorConfig ext_cfg = cfg;
    ext_cfg.extensions.surfaces["target"].threshold_factor = 0.4;
    ext_cfg.extensions.threshold_width = 0.3;
    const auto plain = makeBeamModel(cfg), ext = makeBeamModel(ext_cfg);
    const SensorMount& mount = rig.scene.sensors[size_t(rig.scene.findSensor("hokuyo"))];
    const LaserBeam beam(mount.beamRay(0.0), 0.0);
    int informative = 0;
    for (double rho = 0.0005; rho <= 0.008; rho += 0.0005) {
        rig.scene.volumes[0].timeline = DensityTimeline::constant(rho);
        const SmokeField field = SmokeField::at(rig.scene.volumes, 0.0);
        const BeamWorld w{rig.scene, rig.surfaces, field, false};
        double want = 0;
        for (int i = 0; i < kNormalNodes; ++i) {
            const SmokeField f = field.scaledRegional(std::exp(-0.4 + 0.3 * normalNodes()[i]));
            want += plain->errorProbability(BeamWorld{rig.scene, rig.surfaces, f, false}, beam) / kNormalNodes;
        }
        const double p = ext->errorProbability(w, beam);
        EXPECT_NEAR(p, want, 1e-12) << rho;
        const int n = 1500;
        int err = 0;
        for (int k = 0; k < n; ++k) {
            KeyedRng rng(13, uint64_t(k));
            err += ext->read(w, beam, rng, false).error;
        }
        // The quantile rule is within 1/(2·32) of the average over z, even for a step.
        EXPECT_NEAR(double(err) / n, p, 4 * std::sqrt(std::max(p * (1 - p), 1e-3) / n) + 0.5 / kNormalNodes) << rho;
        informative += p > 0.05 && p < 0.95;
    }
    EXPECT_GE(informative, 3);
}

TEST(Extensions, ShortReturnsAreUniformBeforeTheSurface)
{
    ModelExtensions e;
    e.smoke_obstacle_return = 1.0;
    ExtendedRoom room(e);
    const auto rs = room.read(2 * room.cfg.paper.penetration_power / 2.5, false, 4000);
    double sum = 0;
    int n = 0;
    for (const auto& r : rs)
        if (!r.error) {
            const double m = double(r.value) * 0.001;
            EXPECT_LT(m, 2.5);
            sum += m;
            ++n;
        }
    ASSERT_GT(n, 3900);  // the URG's 20 mm minimum range refuses none: raised to it
    EXPECT_NEAR(sum / n, 1.25, 4 * 2.5 / std::sqrt(12.0 * n));
}

TEST(Extensions, HysteresisMovesTheOnsetWithTheTrend)
{
    // h = 0.6: rising smoke stops beams at P·e^−0.3, falling smoke at P·e^+0.3. At C = P the beam
    // is stopped while rising and passes while falling.
    ModelExtensions e;
    e.hysteresis = 0.6;
    ExtendedRoom room(e);
    const double P = room.cfg.paper.penetration_power;
    for (const auto& [c_over_p, rising, want] : std::vector<std::tuple<double, bool, bool>>{
             {1.0, true, true},
             {1.0, false, false},
             {0.8, true, true},
             {0.68, true, false},
             {1.25, false, false},
             {1.45, false, true}}) {  // each at least 3.6 widths (0.02) from its onset
        const auto rs = room.read(c_over_p * P / 2.5, rising, 50);
        int err = 0;
        for (const auto& r : rs) err += r.error;
        EXPECT_EQ(err, want ? 50 : 0) << "C/P " << c_over_p << (rising ? " rising" : " falling");
    }
}

TEST(Extensions, RangeBiasAndNoiseGrowWithTheColumn)
{
    // The gold reads L(1 + βC) with noise sqrt(σ₀² + (γC)²): β = 12, γ = 4 m per density·m.
    ModelExtensions e;
    e.surfaces["target"].range_bias = 12;
    e.range_noise_growth_m = 4;
    ExtendedRoom room(e);
    const double P = room.cfg.paper.penetration_power, L = 2.5;
    const int n = 4000;
    for (double c_over_p : {0.0, 0.5, 0.9}) {  // 0.9: 5 widths (0.02) below the onset
        const auto rs = room.read(c_over_p * P / L, false, n);
        const double C = c_over_p * P;
        double s = 0, s2 = 0;
        int m = 0;
        for (const auto& r : rs)
            if (!r.error) {
                const double v = double(r.value) * 0.001;
                s += v;
                s2 += v * v;
                ++m;
            }
        ASSERT_EQ(m, n);
        const double mean = s / m, sd = std::sqrt(s2 / m - mean * mean);
        const double sigma = std::hypot(room.model->spec().rangeSigma(L), 4 * C);
        EXPECT_NEAR(mean, L * (1 + 12 * C), 4 * sigma / std::sqrt(m) + 0.0005) << "C/P " << c_over_p;
        EXPECT_NEAR(sd, sigma, 4 * sigma / std::sqrt(2.0 * m) + 0.0003) << "C/P " << c_over_p;
    }
}

TEST(Extensions, WithoutExtensionsTheStreamIsThePaperModels)
{
    // A default ModelExtensions changes nothing: the step at P, and each reading is the surface's
    // range plus the datasheet noise times the stream's first normal draw.
    ExtendedRoom plain(ModelExtensions{});
    const double P = plain.cfg.paper.penetration_power;
    const LrfSpec& spec = plain.model->spec();
    for (double c_over_p : {0.5, 0.999, 1.001}) {
        const auto rs = plain.read(c_over_p * P / 2.5, false, 200);
        for (size_t k = 0; k < rs.size(); ++k) {
            EXPECT_EQ(rs[k].error, c_over_p > 1) << c_over_p;
            if (rs[k].error) continue;
            KeyedRng rng(5, uint64_t(k));
            const double L = rs[k].hit.t_m;
            EXPECT_EQ(rs[k].value, std::llround((L + spec.rangeSigma(L) * rng.normal()) / spec.unit_m)) << k;
        }
    }
}

TEST(Extensions, SensorFileRoundTripsAndRefusesWhatItCannotSimulate)
{
    const auto dir = std::filesystem::temp_directory_path() / "smokescan_test_extensions";
    std::filesystem::create_directories(dir);
    SensorConfig c = SensorConfig::defaults(SensorType::Urg04lx);
    c.extensions.clock_offset_s = 2.5;
    c.extensions.threshold_width = 0.17;
    c.extensions.range_noise_growth_m = 3.25;
    c.extensions.smoke_obstacle_return = 0.3;
    c.extensions.hysteresis = -0.4;
    c.extensions.surfaces["target_gold"] = {0.2, 11.512345678901};
    c.extensions.sectors.push_back({-50.25, -35.123456789, 0.45});
    const std::string path = (dir / "ext.toml").string();
    writeSensorFile(path, c, "test");
    SensorConfig back = SensorConfig::defaults(SensorType::Urg04lx);
    applySensorFile(path, back);
    const ModelExtensions& b = back.extensions;
    EXPECT_EQ(b.clock_offset_s, 2.5);
    EXPECT_EQ(b.threshold_width, 0.17);
    EXPECT_EQ(b.range_noise_growth_m, 3.25);
    EXPECT_EQ(b.smoke_obstacle_return, 0.3);
    EXPECT_EQ(b.hysteresis, -0.4);
    ASSERT_EQ(b.surfaces.count("target_gold"), 1u);
    EXPECT_EQ(b.surfaces.at("target_gold").threshold_factor, 0.2);
    EXPECT_NEAR(b.surfaces.at("target_gold").range_bias, 11.512345678901, 1e-9);
    ASSERT_EQ(b.sectors.size(), 1u);
    EXPECT_EQ(b.sectors[0].from_deg, -50.25);
    EXPECT_NEAR(b.sectors[0].to_deg, -35.123456789, 1e-9);
    EXPECT_EQ(b.sectors[0].dropout, 0.45);
    // Applied twice (a scene's sensor file, then --sensor-file): the section replaces, it does
    // not add a second dropout.
    applySensorFile(path, back);
    EXPECT_EQ(back.extensions.sectors.size(), 1u);

    auto refused = [&](const std::string& text, const std::string& what) {
        const std::string p = (dir / "bad.toml").string();
        std::ofstream(p) << text;
        SensorConfig x = SensorConfig::defaults(SensorType::Urg04lx);
        try {
            applySensorFile(p, x);
            ADD_FAILURE() << "accepted: " << text;
        } catch (const Error& e) {
            const std::string m = e.what();
            EXPECT_NE(m.find(p), std::string::npos) << m;
            EXPECT_NE(m.find(what), std::string::npos) << m;
        }
    };
    const std::string head = "type = \"urg04lx\"\n";
    refused(head + "[extensions]\nhysterisis = 0.2\n", "unknown key 'extensions.hysterisis'");
    refused(head + "[extensions]\n[[extensions.sector]]\nfrom_deg = 1\nto_deg = 2\ndropout = 1.5\n", "dropout");
    refused(head + "[extensions]\n[[extensions.sector]]\nfrom_deg = 3\nto_deg = 2\ndropout = 0.5\n", "to_deg");
    refused(head + "[extensions]\n[[extensions.sector]]\nfrom_deg = 1\nto_deg = 2\n",
            "missing field 'extensions.sector[0].dropout'");
    refused(head + "[extensions]\nrange_noise_growth_m = 1e300\n", "range_noise_growth_m");
    refused(head + "[paper]\npenetration_power = 1e300\n", "penetration_power");
    refused(head + "[extensions]\n[[extensions.surface]]\nname = \"a\"\n[[extensions.surface]]\nname = \"a\"\n",
            "twice");
    refused(head + "[extensions]\nsmoke_obstacle_return = -0.1\n", "smoke_obstacle_return");
    refused(head + "[extensionz]\n", "unknown key 'extensionz'");

    // A surface the scene lacks is refused by the scan, naming the file.
    Rig rig(roomScene(0.001, "gold_paper"));
    ScanConfig sc;
    sc.sensor = "hokuyo";
    sc.model = SensorModel::Paper;
    sc.sensor_file = path;  // names target_gold; the room's target is "target"
    try {
        const Scanner s(rig.scene, rig.surfaces, sc);
        ADD_FAILURE() << "a scan accepted an unknown surface";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("target_gold"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
    // The LMS200's models refuse extensions (a file of that type, and a config).
    {
        const std::string p = (dir / "sick.toml").string();
        std::ofstream(p) << "type = \"lms200\"\n[extensions]\nthreshold_width = 0.3\n";
        SensorConfig sick = SensorConfig::defaults(SensorType::Lms200);
        EXPECT_THROW(applySensorFile(p, sick), Error);
        sick.extensions = back.extensions;
        EXPECT_THROW(makeBeamModel(sick), Error);
    }
    std::filesystem::remove_all(dir);
}

TEST(Extensions, SectorsLieOnTheCircle)
{
    // A laser's sector is the plain interval within its field; the omnicam's may be given anywhere
    // round it, and a bearing unwrapped past a turn is the same bearing.
    const SectorExtension laser{5, 10, 1}, north{-60, 0, 1}, wrapped{300, 360, 1};
    EXPECT_TRUE(laser.contains(7.5));
    EXPECT_FALSE(laser.contains(4.9));
    EXPECT_FALSE(laser.contains(10.1));
    EXPECT_TRUE(laser.contains(367.5));  // 7.5° a turn on
    EXPECT_TRUE(north.contains(330));
    EXPECT_TRUE(north.contains(-30));
    EXPECT_FALSE(north.contains(30));
    EXPECT_TRUE(wrapped.contains(-30));
    EXPECT_TRUE(wrapped.contains(690));
    EXPECT_FALSE(wrapped.contains(10));
    ModelExtensions e;
    e.sectors = {{0, 20, 0.5}, {10, 30, 0.5}};
    EXPECT_DOUBLE_EQ(e.dropoutAt(15), 0.75);  // both: 1 − 0.5·0.5
    EXPECT_DOUBLE_EQ(e.dropoutAt(25), 0.5);
    EXPECT_DOUBLE_EQ(e.dropoutAt(35), 0.0);
}

TEST(Extensions, BoundsAreTheSensorFilesWhereverAModelIsMade)
{
    // The bounds the diagnosis holds a finding to (ModelExtensions::withinBounds) are those the
    // sensor file's reader holds a file to: a model within them is read back, one beyond is refused.
    const auto dir = std::filesystem::temp_directory_path() / "smokescan_test_extension_bounds";
    std::filesystem::create_directories(dir);
    struct Case {
        const char* key;
        double inside, outside;
    };
    const Case cases[] = {{"clock_offset_s", -1e5, 1.0001e5},
                          {"threshold_width", 5, 5.01},
                          {"range_noise_growth_m", 1e3, 1001},
                          {"smoke_obstacle_return", 1, 1.01},
                          {"hysteresis", -10, -10.01}};
    for (const Case& c : cases)
        for (const double v : {c.inside, c.outside}) {
            const std::string p = (dir / "b.toml").string();
            std::ofstream(p) << "type = \"urg04lx\"\n[extensions]\n" << c.key << " = " << v << "\n";
            SensorConfig x = SensorConfig::defaults(SensorType::Urg04lx);
            bool read = true;
            try {
                applySensorFile(p, x);
            } catch (const Error& err) {
                read = false;
                EXPECT_NE(std::string(err.what()).find(c.key), std::string::npos) << err.what();
            }
            EXPECT_EQ(read, v == c.inside) << c.key << " = " << v;
            if (read) EXPECT_TRUE(x.extensions.withinBounds()) << c.key;
            ModelExtensions e;
            if (std::string(c.key) == "clock_offset_s") e.clock_offset_s = v;
            if (std::string(c.key) == "threshold_width") e.threshold_width = v;
            if (std::string(c.key) == "range_noise_growth_m") e.range_noise_growth_m = v;
            if (std::string(c.key) == "smoke_obstacle_return") e.smoke_obstacle_return = v;
            if (std::string(c.key) == "hysteresis") e.hysteresis = v;
            EXPECT_EQ(e.withinBounds(), v == c.inside) << c.key << " = " << v;
        }
    ModelExtensions e;
    e.surfaces["a"] = {10.5, 0};
    EXPECT_FALSE(e.withinBounds());
    e.surfaces["a"] = {0, -2e4};
    EXPECT_FALSE(e.withinBounds());
    e.surfaces.clear();
    e.sectors = {{-361, 0, 0.5}};
    EXPECT_FALSE(e.withinBounds());
    e.sectors = {{300, 360, 0.5}};
    EXPECT_TRUE(e.withinBounds());
    std::filesystem::remove_all(dir);
}
