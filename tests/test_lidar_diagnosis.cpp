// A 3D lidar's frames diagnosed (diagnose/lidar_diagnosis.hpp): the tally's matching, each
// cause's test on synthetic tallies (found with its target, unit pulls, no false alarm beyond the
// level) and on simulated frames with effects planted in the point clouds.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <numeric>
#include <sstream>

#include "diagnose/range_offset_residual.hpp"
#include "error_of.hpp"
#include "scratch.hpp"
#include "smokescan/core/random.hpp"
#include "smokescan/diagnose/lidar_diagnosis.hpp"
#include "smokescan/lidar/frame_index.hpp"
#include "smokescan/lidar/lidar_spec.hpp"
#include "smokescan/lidar/point_cloud_io.hpp"
#include "smokescan/pipeline/lidar_diagnose_run.hpp"
#include "smokescan/scene/scene_io.hpp"

using namespace smokescan;
using smokescan::test::scratch;

namespace {

constexpr double kRadPerDeg = M_PI / 180;

/// A spinning pattern: `channels` rings, `columns` columns a turn at 10 Hz, ring c fired c µs
/// after its column's start.
std::vector<PatternBeam> spinPattern(int channels, int columns)
{
    std::vector<PatternBeam> p;
    for (int k = 0; k < columns; ++k)
        for (int c = 0; c < channels; ++c)
            p.push_back({-M_PI + 2 * M_PI * (k + 0.5) / columns, (c - channels / 2) * kRadPerDeg, c,
                         0.1 * k / columns + c * 1e-6});
    return p;
}

/// A point `range_m` along the beam's direction, with its ring and firing time.
LidarPoint pointOn(const PatternBeam& b, double range_m, double dt_s = 0, double turn_rad = 0)
{
    LidarPoint p;
    const double az = b.azimuth_rad + turn_rad, ce = std::cos(b.elevation_rad);
    p.x = float(range_m * ce * std::cos(az));
    p.y = float(range_m * ce * std::sin(az));
    p.z = float(range_m * std::sin(b.elevation_rad));
    p.range_m = float(range_m);
    p.ring = uint16_t(b.channel);
    p.time_s = float(b.time_s + dt_s);
    return p;
}

/// What a synthetic frame's beams do: each clear at range 5–15 m; a beam's recorded return is
/// dropped with probability `drop(i)` and its range offset by `bias(i)` plus noise of sd `sd`.
struct Synthetic {
    std::vector<PatternBeam> pattern;
    int channels = 16;
    double sd = 0.03;
    std::function<double(size_t)> drop = [](size_t) { return 0.0; };
    std::function<double(size_t)> bias = [](size_t) { return 0.0; };

    double rangeOf(size_t i) const { return 5 + 10 * (0.5 + 0.5 * std::sin(3 * pattern[i].azimuth_rad + i % 7)); }

    LidarTally tally(int frames, uint64_t seed) const
    {
        LidarTally t(pattern, channels, 0.5);
        for (int f = 0; f < frames; ++f) {
            std::vector<ExpectedBeam> ex(pattern.size());
            std::vector<LidarPoint> rec;
            KeyedRng rng(seed, uint64_t(f));
            for (size_t i = 0; i < pattern.size(); ++i) {
                ex[i].range_m = float(rangeOf(i));
                ex[i].clear = true;
                if (rng.uniform() < drop(i)) continue;
                rec.push_back(pointOn(pattern[i], rangeOf(i) + bias(i) + sd * rng.normal()));
            }
            t.add(ex, rec, f % 2);
        }
        return t;
    }
};

const LidarFinding& triedOf(const LidarDiagnosis& d, LidarCause c)
{
    for (const LidarFinding& f : d.tried)
        if (f.cause == c) return f;
    throw std::runtime_error("cause not tried");
}

double sdOf(const std::vector<double>& v)
{
    const double m = std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
    double s = 0;
    for (double x : v) s += (x - m) * (x - m);
    return std::sqrt(s / double(v.size() - 1));
}

}  // namespace

TEST(LidarTally, PointsAreMatchedToTheirBeamByRingAndTimeAndCounted)
{
    const std::vector<PatternBeam> pattern = spinPattern(4, 8);  // 32 beams
    LidarTally t(pattern, 4, 0.5);
    std::vector<ExpectedBeam> ex(pattern.size());
    for (size_t i = 0; i < ex.size(); ++i) {
        ex[i].range_m = 10;
        ex[i].clear = i % 4 != 3;  // ring 3 never clear: not counted
    }
    std::vector<LidarPoint> rec;
    auto point = [&](size_t beam, float range, uint8_t ret = 0, double dt = 0, double turn = 0) {
        LidarPoint p = pointOn(pattern[beam], range, dt, turn);
        p.return_index = ret;
        rec.push_back(p);
    };
    point(0, 10.5f);  // ring 0, column 0: residual +0.5
    point(0, 11.0f, 1);  // its second return: not a first return, ignored
    point(5, 9.0f, 0, 0.004);  // ring 1, column 1 fired 4 ms late: still nearest its own beam (gap 12.5 ms)
    point(4 * 7 + 2, 10.0f);  // ring 2, column 7
    point(4 * 7 + 2, 10.0f);  // the same beam again: unmatched
    point(4 * 4 + 2, 10.0f, 0, 0, 2 * kRadPerDeg);  // ring 2, column 4's time, but 2° off its direction: unmatched
    LidarPoint stray = pointOn(pattern[0], 10);
    stray.ring = 9;  // no such ring
    rec.push_back(stray);
    t.add(ex, rec, 1);
    EXPECT_EQ(t.unmatched(), 3);
    const LidarTally::Fold& f = t.fold(1);
    EXPECT_EQ(std::accumulate(f.clear.begin(), f.clear.end(), 0u), 24u);
    EXPECT_EQ(std::accumulate(f.missed.begin(), f.missed.end(), 0u), 21u);
    EXPECT_EQ(f.missed[0], 0u);
    EXPECT_EQ(f.missed[5], 0u);
    EXPECT_EQ(f.missed[30], 0u);
    ASSERT_EQ(f.residual_m[0].size(), 1u);
    EXPECT_FLOAT_EQ(f.residual_m[0][0], 0.5f);
    EXPECT_FLOAT_EQ(f.residual_m[1][0], -1.0f);
    EXPECT_EQ(std::accumulate(t.fold(0).clear.begin(), t.fold(0).clear.end(), 0u), 0u);
}

TEST(LidarTally, ReturnsAreClassedAgainstTheSurfacesEchoWithinHalfThePulseAndFourSd)
{
    // The VLP-16's preset: a 6 ns pulse (0.899 m of range at FWHM) and a range sd of 1.5 cm.
    const double tol = returnTolerance_m(lidarSpec("vlp16"));
    EXPECT_NEAR(tol, 0.5 * 299792458.0 * 6e-9 / 2 + 4 * 0.015, 1e-3);
    EXPECT_EQ(classifyReturn(0, 10, tol), ReturnClass::None);
    EXPECT_EQ(classifyReturn(10 - tol - 0.01, 10, tol), ReturnClass::Short);
    EXPECT_EQ(classifyReturn(10 - tol + 0.01, 10, tol), ReturnClass::Surface);
    EXPECT_EQ(classifyReturn(10 + tol - 0.01, 10, tol), ReturnClass::Surface);
    EXPECT_EQ(classifyReturn(10 + tol + 0.01, 10, tol), ReturnClass::Beyond);
    EXPECT_EQ(classifyReturn(50, INFINITY, tol), ReturnClass::Short);  // no surface in range: smoke
}

TEST(LidarTally, RangeOffsetResidualIsTheResidualLessTheOffsetsInSd)
{
    const detail::RangeOffsetResidual on(0.10, 0.02, true), off(0.10, 0.02, false);
    const double x[2] = {0.03, 0.05};
    double r = 0;
    on(x, &r);
    EXPECT_NEAR(r, (0.10 - 0.03 - 0.05) / 0.02, 1e-12);
    off(x, &r);
    EXPECT_NEAR(r, (0.10 - 0.03) / 0.02, 1e-12);
}

TEST(LidarDiagnosis, ADroppingChannelIsFoundWithItsRing)
{
    Synthetic s;
    s.pattern = spinPattern(16, 180);
    // Ring 11 loses 30 % of its returns, the others 2 %.
    s.drop = [&](size_t i) { return s.pattern[i].channel == 11 ? 0.30 : 0.02; };
    for (uint64_t seed = 1; seed <= 10; ++seed) {
        const LidarDiagnosis d = diagnoseLidar(s.tally(4, seed), 0.03);
        const LidarFinding& f = triedOf(d, LidarCause::DroppingChannel);
        EXPECT_TRUE(f.named) << seed;
        EXPECT_EQ(f.ring, 11);
        EXPECT_NEAR(f.effect, 0.28, 4 * f.effect_se);
        EXPECT_EQ(d.verdict, "dropping_channel") << seed;
    }
}

TEST(LidarDiagnosis, ASmudgeOnTheWindowIsFoundAsASectorAroundIt)
{
    // Planted as a smooth smudge (dropout 0.7·exp(−½((az − 40°)/8°)²)), not the sector of
    // constant dropout the cause assumes: the sector found must hold the smudge's centre and
    // lie within its 3 sd.
    Synthetic s;
    s.pattern = spinPattern(16, 180);
    s.drop = [&](size_t i) {
        const double u = (s.pattern[i].azimuth_rad / kRadPerDeg - 40) / 8;
        return 0.02 + 0.7 * std::exp(-0.5 * u * u);
    };
    for (uint64_t seed = 1; seed <= 10; ++seed) {
        const LidarDiagnosis d = diagnoseLidar(s.tally(4, seed), 0.03);
        const LidarFinding& f = triedOf(d, LidarCause::WindowSector);
        ASSERT_TRUE(f.named) << seed;
        EXPECT_LE(f.from_deg, 40);
        EXPECT_GE(f.to_deg, 40);
        EXPECT_GE(f.from_deg, 40 - 24);
        EXPECT_LE(f.to_deg, 40 + 24);
        EXPECT_FALSE(triedOf(d, LidarCause::DroppingChannel).named) << seed;
        EXPECT_FALSE(triedOf(d, LidarCause::BiasedChannel).named) << seed;
    }
}

TEST(LidarDiagnosis, AConstantSectorIsFoundWithItsEdgesAlsoAcross180Degrees)
{
    // Half the returns lost on every ring within [30°, 50°), then within [170°, −170°) (across
    // the bins' seam at ±180°): found with their edges, on 5° bins.
    for (const auto& [from, to] : {std::pair{30.0, 50.0}, std::pair{170.0, -170.0}}) {
        Synthetic s;
        s.pattern = spinPattern(16, 360);
        s.drop = [&, from = from, to = to](size_t i) {
            const double az = s.pattern[i].azimuth_rad / kRadPerDeg;
            const bool in = from < to ? az >= from && az < to : az >= from || az < to;
            return in ? 0.5 : 0.02;
        };
        for (uint64_t seed = 1; seed <= 5; ++seed) {
            const LidarDiagnosis d = diagnoseLidar(s.tally(4, seed), 0.03);
            const LidarFinding& f = triedOf(d, LidarCause::WindowSector);
            EXPECT_TRUE(f.named) << from << " " << seed;
            EXPECT_EQ(f.from_deg, from) << seed;
            EXPECT_EQ(f.to_deg, to) << seed;
            EXPECT_NEAR(f.effect, 0.48, 4 * f.effect_se);
            EXPECT_EQ(d.verdict, "window_sector") << seed;
        }
    }
}

TEST(LidarDiagnosis, ABiasedChannelIsFoundWithItsRingAlsoBelowACommonOffset)
{
    // Ring 4 +5 cm (sd 3 cm); then every ring +10 cm and ring 4 5 cm less: −5 cm against the rest.
    for (const auto& [common, own] : {std::pair{0.0, 0.05}, std::pair{0.10, -0.05}}) {
        Synthetic s;
        s.pattern = spinPattern(16, 180);
        s.bias = [&, common = common, own = own](size_t i) { return common + (s.pattern[i].channel == 4 ? own : 0.0); };
        for (uint64_t seed = 1; seed <= 10; ++seed) {
            const LidarDiagnosis d = diagnoseLidar(s.tally(4, seed), 0.03);
            const LidarFinding& f = triedOf(d, LidarCause::BiasedChannel);
            EXPECT_TRUE(f.named) << seed;
            EXPECT_EQ(f.ring, 4);
            EXPECT_NEAR(f.effect, own, 4 * f.effect_se);
            EXPECT_EQ(d.verdict, "biased_channel") << seed;
        }
    }
}

TEST(LidarDiagnosis, EffectsUnderTheirFloorsAreNotNamed)
{
    // A 1 cm bias (a third of the range sd of 3 cm) and a 5 % dropout are real and significant on
    // this many beams, but under the floors (1 sd, 0.1): tested, not named.
    Synthetic s;
    s.pattern = spinPattern(16, 720);
    s.bias = [&](size_t i) { return s.pattern[i].channel == 4 ? 0.01 : 0.0; };
    s.drop = [&](size_t i) { return s.pattern[i].channel == 9 ? 0.07 : 0.02; };
    const LidarDiagnosis d = diagnoseLidar(s.tally(8, 3), 0.03);
    const LidarFinding& b = triedOf(d, LidarCause::BiasedChannel);
    const LidarFinding& c = triedOf(d, LidarCause::DroppingChannel);
    EXPECT_EQ(b.ring, 4);
    EXPECT_LT(b.p_value, 1e-6);
    EXPECT_FALSE(b.named);
    EXPECT_EQ(c.ring, 9);
    EXPECT_LT(c.p_value, 1e-6);
    EXPECT_FALSE(c.named);
    EXPECT_EQ(d.verdict, "none");
}

namespace {

/// A tally of both kinds of beams: rings 0–7 clear (2 % of returns lost, ranges with sd 3 cm),
/// rings 8–15 in smoke, their first return none, short or at their surface (ring % 4) with the
/// replay's chances 0.3, 0.2, 0.5; recorded with those chances, or surface 2's returns at
/// `surface2` instead of 0.5 (the rest none).
/// Four frames of a 16-ring pattern (even frames fold 0), each beam's replay and recorded
/// points made by `beam(i, replay, rng, recorded)`.
template <typename Beam>
LidarTally tallyOf(const std::vector<PatternBeam>& pattern, uint64_t seed, Beam beam)
{
    LidarTally t(pattern, 16, 0.5);
    for (int fr = 0; fr < 4; ++fr) {
        std::vector<ExpectedBeam> ex(pattern.size());
        std::vector<LidarPoint> rec;
        KeyedRng rng(seed, uint64_t(fr));
        for (size_t i = 0; i < pattern.size(); ++i) beam(i, ex[i], rng, rec);
        t.add(ex, rec, fr % 2);
    }
    return t;
}

LidarTally mixedTally(uint64_t seed, double surface2 = 0.5)
{
    const std::vector<PatternBeam> pattern = spinPattern(16, 180);
    return tallyOf(pattern, seed, [&](size_t i, ExpectedBeam& x, KeyedRng& rng, std::vector<LidarPoint>& rec) {
        x.surface = pattern[i].channel % 4;
        x.surface_range_m = 10;
        x.range_m = 10;
        if (pattern[i].channel < 8) {
            x.clear = true;
            x.p_none = 0, x.p_surface = 1;
            if (rng.uniform() >= 0.02) rec.push_back(pointOn(pattern[i], 10 + 0.03 * rng.normal()));
            return;
        }
        x.p_none = 0.3f, x.p_short = 0.2f, x.p_surface = 0.5f;
        const double u = rng.uniform(), at_surface = x.surface == 2 ? surface2 : 0.5;
        if (u < 0.2)
            rec.push_back(pointOn(pattern[i], 4));  // a smoke echo 6 m short
        else if (u < 0.2 + at_surface)
            rec.push_back(pointOn(pattern[i], 10 + 0.03 * rng.normal()));
    });
}

}  // namespace

TEST(LidarDiagnosis, ASurfaceReturnedLessThanItsChanceInSmokeIsFoundByName)
{
    // Surface 2 returned at 0.25 instead of 0.5: given not short, 0.3125 against its 0.625.
    for (uint64_t seed = 1; seed <= 10; ++seed) {
        const LidarDiagnosis d = diagnoseLidar(mixedTally(seed, 0.25), 0.03);
        const LidarFinding& f = triedOf(d, LidarCause::SurfaceThreshold);
        EXPECT_TRUE(f.named) << seed;
        EXPECT_EQ(f.surface, 2);
        EXPECT_NEAR(f.effect, -0.3125, 4 * f.effect_se);
        EXPECT_EQ(d.verdict, "surface_threshold") << seed;
    }
}

TEST(LidarDiagnosis, ASurfaceWhoseCertainEchoesGoMissingIsFoundByNameNotAsASectorOrAChannel)
{
    // Clear air: every beam certain. A wall (surface 3) fills azimuths 30–60° on rings 0–9, the
    // rest is surface 1; the wall's beams miss 40 %, the others 1 %. The wall is a sector and most
    // of ten rings too: it is named as itself (its returns 0.39 under the others'), and neither a
    // window's sector nor a channel is named beside it.
    const std::vector<PatternBeam> pattern = spinPattern(16, 180);
    auto onWall = [&](size_t i) {
        const double deg = pattern[i].azimuth_rad / kRadPerDeg;
        return deg >= 30 && deg <= 60 && pattern[i].channel < 10;
    };
    for (uint64_t seed : {1, 2, 3}) {
        const LidarTally t =
            tallyOf(pattern, seed, [&](size_t i, ExpectedBeam& x, KeyedRng& rng, std::vector<LidarPoint>& rec) {
                x.clear = true;
                x.range_m = x.surface_range_m = 10;
                x.p_none = 0, x.p_surface = 1;
                x.surface = onWall(i) ? 3 : 1;
                if (rng.uniform() >= (onWall(i) ? 0.40 : 0.01))
                    rec.push_back(pointOn(pattern[i], 10 + 0.03 * rng.normal()));
            });
        const LidarDiagnosis d = diagnoseLidar(t, 0.03);
        const LidarFinding& f = triedOf(d, LidarCause::SurfaceThreshold);
        EXPECT_EQ(d.verdict, "surface_threshold") << seed;
        EXPECT_EQ(f.surface, 3);
        EXPECT_NEAR(f.effect, -0.39, 4 * f.effect_se);
    }
}

TEST(LidarDiagnosisStats, CleanTalliesGiveEveryCauseUniformHeldOutPValuesAndUnitPulls)
{
    // 200 clean runs without floors: each cause's held-out p is uniform (a test searched and
    // tested on the same frames, a one- for a two-sided p on a two-sided estimate, or a wrong se
    // shows here), and the estimates' z have mean 0 and sd 1.
    constexpr int kSeeds = 200;
    std::map<LidarCause, std::vector<double>> p, z;
    int named = 0;
    for (uint64_t seed = 1; seed <= kSeeds; ++seed) {
        LidarDiagnosisConfig cfg;
        cfg.min_dropout = 0;
        cfg.min_bias_sd = 0;
        const LidarDiagnosis d = diagnoseLidar(mixedTally(seed), 0.03, cfg);
        named += d.verdict != "none";
        for (const LidarFinding& f : d.tried) {
            ASSERT_TRUE(f.tested) << lidarCauseName(f.cause);
            p[f.cause].push_back(f.p_value);
            z[f.cause].push_back(f.effect / f.effect_se);
        }
    }
    auto below = [&](LidarCause c, double a) {
        return double(std::count_if(p[c].begin(), p[c].end(), [&](double x) { return x < a; })) / kSeeds;
    };
    for (const auto& [cause, ps] : p) {
        // Valid: no more small p than the level (a test searched and tested on the same frames
        // gives far more). The dropouts' tests count few misses on a narrow candidate (often
        // none): discrete and conservative, so only bounded above.
        EXPECT_LE(below(cause, 0.05), 0.10) << lidarCauseName(cause);
        EXPECT_LE(below(cause, 0.2), 0.3) << lidarCauseName(cause);
    }
    for (LidarCause c : {LidarCause::BiasedChannel, LidarCause::SmokeFirstReturns, LidarCause::SurfaceThreshold}) {
        EXPECT_GE(below(c, 0.05), 0.01) << lidarCauseName(c);  // and uniform where the counts are large
        EXPECT_NEAR(below(c, 0.5), 0.5, 0.1) << lidarCauseName(c);
    }
    // The two-sided estimates: unbiased with their stated se (one-sided ones are chosen to exceed).
    for (LidarCause c : {LidarCause::BiasedChannel, LidarCause::SmokeFirstReturns, LidarCause::SurfaceThreshold}) {
        const std::vector<double>& v = z[c];
        EXPECT_NEAR(std::accumulate(v.begin(), v.end(), 0.0) / kSeeds, 0, 0.2) << lidarCauseName(c);
        EXPECT_NEAR(sdOf(v), 1.0, 0.15) << lidarCauseName(c);
        std::printf("%s: z mean %.3f sd %.3f; p < 0.05: %.3f, < 0.2: %.3f, < 0.5: %.3f\n", lidarCauseName(c),
                    std::accumulate(v.begin(), v.end(), 0.0) / kSeeds, sdOf(v), below(c, 0.05), below(c, 0.2),
                    below(c, 0.5));
    }
    // At level 0.05 over five causes, a run names one with probability at most 0.05.
    EXPECT_LE(named, 20);
}

TEST(LidarDiagnosisStats, PlantedDropoutAndBiasAreEstimatedWithUnitPulls)
{
    constexpr int kSeeds = 200;
    Synthetic drop;
    drop.pattern = spinPattern(16, 180);
    drop.drop = [&](size_t i) { return drop.pattern[i].channel == 11 ? 0.30 : 0.02; };
    Synthetic bias;
    bias.pattern = drop.pattern;
    bias.bias = [&](size_t i) { return 0.10 + (bias.pattern[i].channel == 4 ? -0.05 : 0.0); };
    std::vector<double> pull_drop, pull_bias;
    for (uint64_t seed = 1; seed <= kSeeds; ++seed) {
        const LidarFinding d = triedOf(diagnoseLidar(drop.tally(4, seed), 0.03), LidarCause::DroppingChannel);
        ASSERT_EQ(d.ring, 11);
        pull_drop.push_back((d.effect - 0.28) / d.effect_se);
        const LidarFinding b = triedOf(diagnoseLidar(bias.tally(4, seed + 1000), 0.03), LidarCause::BiasedChannel);
        ASSERT_EQ(b.ring, 4);
        pull_bias.push_back((b.effect + 0.05) / b.effect_se);
    }
    for (const std::vector<double>* v : {&pull_drop, &pull_bias}) {
        EXPECT_NEAR(std::accumulate(v->begin(), v->end(), 0.0) / kSeeds, 0, 0.2);
        EXPECT_NEAR(sdOf(*v), 1.0, 0.15);
    }
}

TEST(LidarDiagnosis, AFoldWithoutClearBeamsIsRefused)
{
    Synthetic s;
    s.pattern = spinPattern(4, 8);
    EXPECT_NE(test::errorOf([&] { diagnoseLidar(s.tally(1, 1), 0.03); }).find("odd frames have no beam"),
              std::string::npos);
}

TEST(FrameIndex, BadLinesAreOneLineErrorsNamingTheLine)
{
    std::string head = frameIndexHeader();
    const std::string pose = "0,0,0,1,0,0,0";
    const std::string good =
        head + "0,a.pcd,0,0.1," + pose + "," + pose + "\n" + "1,b.pcd,0.1,0.2," + pose + "," + pose + "\n";
    const std::vector<FrameIndexEntry> e = parseFrameIndex(good, "f.csv");
    ASSERT_EQ(e.size(), 2u);
    EXPECT_EQ(e[1].file, "b.pcd");
    EXPECT_DOUBLE_EQ(e[1].start_s, 0.1);
    auto err = [&](const std::string& text) { return test::errorOf([&] { parseFrameIndex(text, "f.csv"); }); };
    EXPECT_NE(err("frame,file\n").find("f.csv:1: the header"), std::string::npos);
    EXPECT_NE(err("").find("f.csv: is empty"), std::string::npos);
    EXPECT_NE(err(head + "0,a.pcd,0,0.1\n").find("f.csv:2: 4 fields"), std::string::npos);
    EXPECT_NE(err(head + "0,../a.pcd,0,0.1," + pose + "," + pose + "\n").find("inside the folder"), std::string::npos);
    EXPECT_NE(err(head + "0,a.pcd,nan,0.1," + pose + "," + pose + "\n").find("f.csv:2"), std::string::npos);
    EXPECT_NE(err(head + "0,a.pcd,0.2,0.1," + pose + "," + pose + "\n").find("precedes"), std::string::npos);
    EXPECT_NE(err(good + "2,c.pcd,0.1,0.3," + pose + "," + pose + "\n").find("f.csv:4: start_s"), std::string::npos);
    EXPECT_NE(err(good + "2,a.pcd,0.3,0.3," + pose + "," + pose + "\n").find("listed twice"), std::string::npos);
    EXPECT_NE(err(head + "0,a.pcd,0,0.1,0,0,0,2,0,0,0," + pose + "\n").find("norm 1"), std::string::npos);
    EXPECT_NE(err(head + "-1,a.pcd,0,0.1," + pose + "," + pose + "\n").find("frame index"), std::string::npos);
}

namespace {

/// Six frames of a lidar (a preset's name or file) in `scene` from t0.
std::vector<LidarFrame> simulateLidarRun(const Scene& scene, const std::string& sensor, double t0,
                                         const std::string& returns = "", double rate_hz = 0)
{
    LidarRunConfig c;
    c.sensor = sensor;
    c.returns = returns;
    c.rate_hz = rate_hz;
    c.from_s = t0;
    c.to_s = t0 + 0.55;
    c.seed = 7;
    return LidarRun(scene, c).collect();
}

/// A VLP-16 driving through the factory as smoke fills it: six frames from 38 s (the smoke hides
/// most of the hall: about one beam in eight is clear), kept in memory (one simulation for every
/// plant below).
const std::vector<LidarFrame>& factoryFrames()
{
    static const std::vector<LidarFrame> frames = simulateLidarRun(loadScene("factory_smoke"), "vlp16", 38);
    return frames;
}

/// The frames with `plant` applied to each, written as `smokescan scan --points` writes them.
std::string writePlantedFrames(const std::string& name, const std::function<void(LidarFrame&, KeyedRng&)>& plant,
                               const std::vector<LidarFrame>& frames = factoryFrames())
{
    const std::filesystem::path dir = scratch("lidar_diagnosis_" + name);
    std::ofstream index(dir / "frames.csv");
    index << frameIndexHeader();
    for (LidarFrame f : frames) {
        KeyedRng rng(99, f.index);
        plant(f, rng);
        const std::string file = std::to_string(f.index) + ".pcd";
        writePcd((dir / file).string(), f);
        index << frameIndexRow(f, file);
    }
    return dir.string();
}

LidarDiagnosis diagnoseFrames(const std::string& dir)
{
    LidarDiagnoseRunConfig cfg;
    cfg.scene = "factory_smoke";
    cfg.points = dir;
    cfg.sensor.sensor = "vlp16";
    return runLidarDiagnosis(cfg).diagnosis;
}

/// The factory's six frames at 38 s replayed once (the replay is the costly part), and a
/// diagnosis of any frames recorded at those times against it: runLidarDiagnosis without the
/// files (the tests above and below go through them).
LidarDiagnosis diagnoseAgainstReplay(const std::vector<LidarFrame>& frames,
                                     const std::function<void(LidarFrame&, KeyedRng&)>& plant)
{
    static const Scene scene = loadScene("factory_smoke");
    static LidarRunConfig config = [] {
        LidarRunConfig c;
        c.sensor = "vlp16";
        c.from_s = 38;
        return c;
    }();
    static const LidarRun run(scene, config);
    static const std::vector<std::vector<ExpectedBeam>> replay = [&] {
        std::vector<std::vector<ExpectedBeam>> r;
        for (const LidarFrame& f : factoryFrames()) r.push_back(run.scanner().expected(f.start_s));
        return r;
    }();
    LidarTally tally(run.scanner().pattern(), run.spec().channels(), returnTolerance_m(run.spec()));
    for (size_t k = 0; k < frames.size(); ++k) {
        EXPECT_EQ(frames[k].start_s, factoryFrames()[k].start_s);
        LidarFrame f = frames[k];
        KeyedRng rng(99, f.index);
        plant(f, rng);
        tally.add(replay[k], f.points, int(k % 2));
    }
    LidarDiagnosis d = diagnoseLidar(tally, run.spec().range_sigma_m);
    for (const Surface& sf : scene.surfaces) d.surface_names.push_back(sf.name);
    return d;
}

/// The ring with the most clear beams in the clean run (a plant there has beams to show on).
int busiestRing(const LidarDiagnosis& d)
{
    size_t best = 0;
    for (size_t c = 1; c < d.rings.size(); ++c)
        if (d.rings[c].clear > d.rings[best].clear) best = c;
    return int(best);
}

void removeIf(LidarFrame& f, const std::function<bool(const LidarPoint&)>& gone)
{
    f.points.erase(std::remove_if(f.points.begin(), f.points.end(), gone), f.points.end());
}

/// A weak channel: `ring`'s faint returns (under its median intensity in the frame) lost 70 % of
/// the time, its bright ones 20 % (where the dropping channel's cause assumes one rate a ring).
void weakenFaintReturns(LidarFrame& f, int ring, KeyedRng& rng)
{
    std::vector<float> in;
    for (const LidarPoint& p : f.points)
        if (p.ring == ring) in.push_back(p.intensity);
    if (in.empty()) return;
    std::nth_element(in.begin(), in.begin() + long(in.size() / 2), in.end());
    const float median = in[in.size() / 2];
    removeIf(f,
             [&](const LidarPoint& p) { return p.ring == ring && rng.uniform() < (p.intensity < median ? 0.7 : 0.2); });
}

}  // namespace

TEST(LidarDiagnosisRun, SimulatedFramesInSmokeNameNothingAndMatchTheirReplay)
{
    const std::string dir = writePlantedFrames("clean", [](LidarFrame&, KeyedRng&) {});
    // Frame 3's recorded start pose 5 cm east of the scene's and turned by 0.5° about its z axis:
    // reported as the poses' difference (the replay keeps the scene's).
    {
        std::ifstream in(dir + "/frames.csv");
        std::vector<std::string> lines;
        for (std::string l; std::getline(in, l);) lines.push_back(l);
        std::vector<std::string> f;
        std::stringstream row(lines[4]);
        for (std::string cell; std::getline(row, cell, ',');) f.push_back(cell);
        ASSERT_EQ(f.size(), 18u);
        f[4] = std::to_string(std::stod(f[4]) + 0.05);
        const Eigen::Quaterniond q =
            Eigen::Quaterniond(std::stod(f[7]), std::stod(f[8]), std::stod(f[9]), std::stod(f[10])) *
            Eigen::Quaterniond(Eigen::AngleAxisd(0.5 * kRadPerDeg, Vec3::UnitZ()));
        char buf[160];
        std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g,%.17g", q.w(), q.x(), q.y(), q.z());
        lines[4].clear();
        for (size_t k = 0; k < f.size(); ++k) {
            if (k == 7) {
                lines[4] += std::string(buf) + ",";
                k = 10;
                continue;
            }
            lines[4] += f[k] + (k + 1 < f.size() ? "," : "");
        }
        std::ofstream out(dir + "/frames.csv");
        for (const std::string& l : lines) out << l << "\n";
    }
    const LidarDiagnosis d = diagnoseFrames(dir);
    EXPECT_EQ(d.verdict, "none");
    EXPECT_EQ(d.frames, 6u);
    EXPECT_EQ(d.beams, 6 * 16 * 1808);  // the preset's 1808 columns a turn at 10 Hz
    // Most beams see their surface for certain, in clear air or rising out of the smoke's echo
    // (the receiver's peaks); the rest are in the densest smoke or cross an edge. The receiver
    // that dropped a wall's echo merged into the near field's smoke was sure of under a fifth.
    EXPECT_GT(d.clear, d.beams / 2);
    EXPECT_LT(d.clear, d.beams * 9 / 10);
    EXPECT_EQ(d.unmatched_points, 0);
    EXPECT_NEAR(d.pose_mismatch_m, 0.05, 1e-5);
    EXPECT_NEAR(d.pose_mismatch_deg, 0.5, 1e-5);
    // The clear beams' residuals are the preset's range noise (VLP-16: 1.5 cm, the datasheet's
    // ±3 cm as 2 sd) and nearly all certain echoes were recorded.
    EXPECT_NEAR(d.range_sd_m, 0.015, 0.004);
    long long missed = 0;
    for (const LidarGroupStats& g : d.rings) missed += g.missed;
    EXPECT_LT(double(missed) / double(d.clear), 0.01);
}

TEST(LidarDiagnosisRun, ChannelWindowAndBiasPlantedInThePointCloudsAreFoundWithTheirTargets)
{
    const LidarDiagnosis clean = diagnoseAgainstReplay(factoryFrames(), [](LidarFrame&, KeyedRng&) {});
    const int ring = busiestRing(clean);
    float minRange = 1e9f, maxRange = 0;
    for (const LidarFrame& f : factoryFrames())
        for (const LidarPoint& p : f.points)
            if (p.ring == ring) minRange = std::min(minRange, p.range_m), maxRange = std::max(maxRange, p.range_m);
    // A weak channel: its faint returns (under the ring's median intensity) lost more often than
    // its bright ones (70 % against 20 %), where the cause assumes one rate a ring.
    {
        const LidarDiagnosis d = diagnoseAgainstReplay(
            factoryFrames(), [&](LidarFrame& f, KeyedRng& rng) { weakenFaintReturns(f, ring, rng); });
        EXPECT_EQ(d.verdict, "dropping_channel");
        EXPECT_EQ(triedOf(d, LidarCause::DroppingChannel).ring, ring);
        // Between the bright returns' loss and the faint ones' (the clear beams are mostly bright).
        EXPECT_GT(triedOf(d, LidarCause::DroppingChannel).effect,
                  0.2 - 4 * triedOf(d, LidarCause::DroppingChannel).effect_se);
        EXPECT_LT(triedOf(d, LidarCause::DroppingChannel).effect, 0.7);
    }
    // Soot on the window: every ring's points behind a smudge (dropout 0.8 at azimuth `at` in the
    // sensor frame, falling off as a Gaussian of 6°), by the point's own direction; `at` where the
    // clean run's clear beams are densest over 30° (the smoke hides the rest).
    {
        const size_t bins = clean.sectors.size();
        size_t densest = 0;
        long long most = -1;
        for (size_t b = 0; b < bins; ++b) {
            long long n = 0;
            for (int k = -2; k <= 2; ++k) n += clean.sectors[(b + bins + size_t(k)) % bins].clear;
            if (n > most) most = n, densest = b;
        }
        const double at = -180 + (double(densest) + 0.5) * clean.sector_deg;
        const LidarDiagnosis d = diagnoseAgainstReplay(factoryFrames(), [&](LidarFrame& f, KeyedRng& rng) {
            removeIf(f, [&](const LidarPoint& p) {
                const double u = std::remainder(std::atan2(p.y, p.x) / kRadPerDeg - at, 360.0) / 6;
                return rng.uniform() < 0.8 * std::exp(-0.5 * u * u);
            });
        });
        EXPECT_EQ(d.verdict, "window_sector");
        const LidarFinding& w = triedOf(d, LidarCause::WindowSector);
        // The sector holds the smudge's centre and lies within its 3 sd (no sector across ±180°
        // here: the densest bins are not there).
        ASSERT_LT(std::abs(at), 150) << "the smudge's centre";
        EXPECT_LE(w.from_deg, at);
        EXPECT_GE(w.to_deg, at);
        EXPECT_GE(w.from_deg, at - 18);
        EXPECT_LE(w.to_deg, at + 18);
    }
    // A channel whose ranges are stretched by 4 % (a clock error), not offset by a constant.
    {
        const LidarDiagnosis d = diagnoseAgainstReplay(factoryFrames(), [&](LidarFrame& f, KeyedRng&) {
            for (LidarPoint& p : f.points)
                if (p.ring == ring) {
                    p.x *= 1.04f;
                    p.y *= 1.04f;
                    p.z *= 1.04f;
                    p.range_m *= 1.04f;
                }
        });
        EXPECT_EQ(d.verdict, "biased_channel");
        const LidarFinding& b = triedOf(d, LidarCause::BiasedChannel);
        EXPECT_EQ(b.ring, ring);
        // 4 % of the ring's ranges: between 4 % of its nearest and of its farthest clear return.
        EXPECT_GT(b.effect, 0.04 * minRange);
        EXPECT_LT(b.effect, 0.04 * maxRange);
    }
}

TEST(LidarDiagnosisRun, TheExtendedPresetExplainsHeldOutFramesOfTheSameFaults)
{
    // Two faults through mechanisms the causes do not assume: a weak channel (its faint returns
    // lost 70 % of the time, its bright ones 20 %) and another whose ranges stretch by 4 %. The
    // diagnosis of the frames at 38 s writes the extended preset; six other frames (at 41 s, other
    // noise) with the same faults are then diagnosed against the preset and against its extension.
    const LidarDiagnosis clean = diagnoseAgainstReplay(factoryFrames(), [](LidarFrame&, KeyedRng&) {});
    const int weak = busiestRing(clean), stretched = (weak + 8) % 16;
    const auto faults = [&](LidarFrame& f, KeyedRng& rng) {
        weakenFaintReturns(f, weak, rng);
        for (LidarPoint& p : f.points)
            if (p.ring == stretched) p.x *= 1.04f, p.y *= 1.04f, p.z *= 1.04f, p.range_m *= 1.04f;
    };
    LidarDiagnoseRunConfig cfg;
    cfg.scene = "factory_smoke";
    cfg.points = writePlantedFrames("extend_search", faults);
    cfg.sensor.sensor = "vlp16";
    const LidarDiagnoseRunResult found = runLidarDiagnosis(cfg);
    // (The weak channel's faint returns lost on the beams that are not clear also show as a
    // surface's threshold where that ring meets one: not an extension yet, named in a comment.)
    ASSERT_EQ(found.diagnosis.verdict.rfind("dropping_channel, biased_channel", 0), 0u)
        << found.diagnosis.extended_preset;
    const std::string preset = (scratch("lidar_extended") / "lidar.toml").string();
    std::ofstream(preset) << found.diagnosis.extended_preset;
    const LidarSpec spec = lidarSpec(preset);
    EXPECT_EQ(spec.name, "vlp16-extended");
    ASSERT_EQ(spec.extensions.channels.size(), 2u) << found.diagnosis.extended_preset;
    const LidarFinding& dropping = triedOf(found.diagnosis, LidarCause::DroppingChannel);
    EXPECT_NEAR(spec.extensions.dropout(weak, 0), dropping.effect / (1 - dropping.base_rate), 1e-5);
    EXPECT_NEAR(spec.extensions.rangeOffset_m(stretched), triedOf(found.diagnosis, LidarCause::BiasedChannel).effect,
                1e-5);

    // Held out: other frames, the same faults.
    cfg.points =
        writePlantedFrames("extend_heldout", faults, simulateLidarRun(loadScene("factory_smoke"), "vlp16", 41));
    const LidarDiagnosis before = runLidarDiagnosis(cfg).diagnosis;
    cfg.sensor.sensor = preset;
    const LidarDiagnosis after = runLidarDiagnosis(cfg).diagnosis;
    const LidarFinding &b0 = triedOf(before, LidarCause::BiasedChannel),
                       &b1 = triedOf(after, LidarCause::BiasedChannel);
    const LidarFinding &d0 = triedOf(before, LidarCause::DroppingChannel),
                       &d1 = triedOf(after, LidarCause::DroppingChannel);
    std::printf(
        "held out, preset: %s; extended: %s\n  dropping ring %d: effect %.3f gain %.0f nats -> ring %d "
        "effect %.3f gain %.0f\n  biased ring %d: %.3f m gain %.0f nats -> ring %d %.3f m gain %.0f\n",
        before.verdict.c_str(), after.verdict.c_str(), d0.ring, d0.effect, d0.gain_nats, d1.ring, d1.effect,
        d1.gain_nats, b0.ring, b0.effect, b0.gain_nats, b1.ring, b1.effect, b1.gain_nats);
    EXPECT_EQ(before.verdict.rfind("dropping_channel, biased_channel", 0), 0u) << before.verdict;
    // The extension explains the weak channel (its beams judged by their chances, not as certain)
    // and the stretched one's bias; neither is named again. (What the extension cannot say, that the
    // weak channel loses its faint returns more than its bright ones, may still show as a surface's
    // threshold on the beams that are not clear.)
    EXPECT_EQ(after.verdict.find("dropping_channel"), std::string::npos) << after.verdict;
    EXPECT_EQ(after.verdict.find("biased_channel"), std::string::npos) << after.verdict;
    EXPECT_FALSE(d1.named && d1.ring == weak);
    EXPECT_LT(b1.gain_nats, 0.05 * b0.gain_nats);
    // And it says what the held-out frames show: the dropout found at 38 s is the one that gives
    // the weak ring's excess at 41 s (within both errors), the offset the stretched ring's bias
    // there (within 0.03 m: the stretch is 4 % of other ranges there).
    EXPECT_EQ(d0.ring, weak);
    EXPECT_NEAR(spec.extensions.dropout(weak, 0), d0.effect / (1 - d0.base_rate),
                4 * std::hypot(dropping.effect_se, d0.effect_se));
    EXPECT_NEAR(spec.extensions.rangeOffset_m(stretched), b0.effect, 0.03);
    // The stretch is not an offset: what is left on the ring is its spread of ranges' share, a
    // fraction of what the preset left.
    if (b1.ring == stretched) EXPECT_LT(std::abs(b1.effect), 0.25 * std::abs(b0.effect));
}

TEST(LidarDiagnosisRun, SmokeEchoesTakenAsFirstReturnsAreFound)
{
    // The recorder is a VLP-16 that reports each beam's first echo (a preset that offers it),
    // the diagnosis assumes the strongest: in the factory's thinner smoke at 20 s the first echo
    // is often the smoke's. The cause assumes only "more short returns than their chance".
    const Scene scene = loadScene("factory_smoke");
    const std::filesystem::path dir = scratch("lidar_diagnosis_first");
    std::string preset;
    {
        std::ifstream in(std::string(SMOKESCAN_SOURCE_DIR) + "/presets/lidar/vlp16.toml");
        std::stringstream ss;
        ss << in.rdbuf();
        preset = ss.str();
    }
    const std::string modes = "return_modes = [\"strongest\", \"last\", \"dual\"]";
    ASSERT_NE(preset.find(modes), std::string::npos);
    preset.replace(preset.find(modes), modes.size(), "return_modes = [\"first\", \"strongest\", \"last\", \"dual\"]");
    std::ofstream((dir / "vlp16_first.toml").string()) << preset;
    const auto none = [](LidarFrame&, KeyedRng&) {};
    const LidarDiagnosis clean =
        diagnoseFrames(writePlantedFrames("first_clean", none, simulateLidarRun(scene, "vlp16", 20)));
    EXPECT_EQ(clean.verdict, "none");
    const LidarDiagnosis d = diagnoseFrames(
        writePlantedFrames("first", none, simulateLidarRun(scene, (dir / "vlp16_first.toml").string(), 20, "first")));
    EXPECT_EQ(d.verdict, "smoke_first_returns");
    const LidarFinding& f = triedOf(d, LidarCause::SmokeFirstReturns);
    EXPECT_GT(f.effect, 0.1);  // of the beams in smoke that could return, a tenth more return short (seen 0.15)
    EXPECT_GT(f.effect, 10 * f.effect_se);
}

TEST(LidarDiagnosisRun, ASurfaceDarkerThanTheSceneSaysIsFoundByName)
{
    // The recorded room's surface seen most in the smoke at 38 s reflects 30 % of what the scene
    // says in the near infrared (its own material): planted as reflectance, where the cause
    // assumes a share of returns off their chance.
    const LidarDiagnosis clean = diagnoseAgainstReplay(factoryFrames(), [](LidarFrame&, KeyedRng&) {});
    int surface = -1;
    long long most = 0;
    for (const auto& [sf, o] : clean.surfaces)
        if (o.beams > most) most = o.beams, surface = sf;
    ASSERT_GE(surface, 0);
    ASSERT_GT(most, 500);
    Scene dark = loadScene("factory_smoke");
    Material m = dark.materials[size_t(dark.surfaces[size_t(surface)].material)];
    m.name += "_dark";
    m.nir_785 *= 0.3;
    m.nir_905 *= 0.3;
    dark.materials.push_back(m);
    dark.surfaces[size_t(surface)].material = int(dark.materials.size() - 1);
    const LidarDiagnosis d = diagnoseAgainstReplay(simulateLidarRun(dark, "vlp16", 38), [](LidarFrame&, KeyedRng&) {});
    const LidarFinding& f = triedOf(d, LidarCause::SurfaceThreshold);
    EXPECT_TRUE(f.named);
    EXPECT_EQ(f.surface, surface);
    EXPECT_EQ(d.surface_names[size_t(f.surface)], clean.surface_names[size_t(surface)]);
    // Fewer returns than their chance, by more than the floor; and its clear beams (certain at
    // the scene's reflectance) that go missing are its own, not a dirty window's sector or a
    // channel's, nor are the ranges its darker echoes read at a channel's bias.
    EXPECT_LT(f.effect, -0.1);
    EXPECT_GT(std::abs(f.effect), 5 * f.effect_se);
    EXPECT_EQ(d.verdict, "surface_threshold");
    EXPECT_FALSE(triedOf(d, LidarCause::SmokeFirstReturns).named);
}

TEST(LidarDiagnosisRun, AFrameOfNoPointIsLeftOutNotReadAsEveryBeamMissing)
{
    // A recorder's dropped frame (a message of no point) says nothing about the sensor: left out
    // and counted, not read as every beam of the frame unanswered (one frame of six was a sixth of
    // the clear beams missing, a third of the odd fold's).
    const LidarDiagnosis d = diagnoseFrames(writePlantedFrames("one_empty", [](LidarFrame& f, KeyedRng&) {
        if (f.index == 3) f.points.clear();
    }));
    EXPECT_EQ(d.empty_frames, 1u);
    EXPECT_EQ(d.frames, 5u);
    long long missed = 0;
    for (const LidarGroupStats& g : d.rings) missed += g.missed;
    EXPECT_LT(double(missed), 0.01 * double(d.clear)) << missed << " of " << d.clear;
    EXPECT_EQ(d.verdict, "none");
    // Empty in effect: of the first five frames, two keep one point each (a cut message), and the
    // frames kept alternate between the folds (the listing's odd frames, 1 and 3, left the
    // held-out fold none: "the odd frames have no beam the replay is sure of").
    const std::vector<LidarFrame> five(factoryFrames().begin(), factoryFrames().begin() + 5);
    const LidarDiagnosis cut = diagnoseFrames(writePlantedFrames(
        "two_cut",
        [](LidarFrame& f, KeyedRng&) {
            if (f.index == 1 || f.index == 3) f.points.resize(1);
        },
        five));
    EXPECT_EQ(cut.empty_frames, 2u);
    EXPECT_EQ(cut.frames, 3u);
    missed = 0;
    for (const LidarGroupStats& g : cut.rings) missed += g.missed;
    EXPECT_LT(double(missed), 0.01 * double(cut.clear)) << missed << " of " << cut.clear;
    EXPECT_EQ(cut.verdict, "none");
    // A frame the driver wrote whole with every beam "no return" (NaN, as an organized cloud
    // does) is a reading, not a dropped frame: kept, its beams missed. A bare message of no point
    // and no fields (a recorder's) is left out, not refused for its missing ring field.
    const std::string blind = writePlantedFrames("blind_and_bare", [](LidarFrame& f, KeyedRng&) {
        if (f.index == 3)
            for (LidarPoint& p : f.points) p.x = std::numeric_limits<float>::quiet_NaN();
    });
    std::ofstream(blind + "/1.pcd") << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 0\n"
                                       "HEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 0\nDATA ascii\n";
    const LidarDiagnosis b = diagnoseFrames(blind);
    EXPECT_EQ(b.empty_frames, 1u);
    EXPECT_EQ(b.frames, 5u);
    missed = 0;
    for (const LidarGroupStats& g : b.rings) missed += g.missed;
    EXPECT_GT(double(missed), 0.15 * double(b.clear)) << missed << " of " << b.clear;
    // A frame of second returns alone is empty: its NaN "no return" slots of return index 1
    // (a dual driver's organized cloud) do not make it a reading.
    const LidarDiagnosis second = diagnoseFrames(writePlantedFrames("second_alone", [](LidarFrame& f, KeyedRng&) {
        if (f.index == 3)
            for (LidarPoint& p : f.points) p.x = std::numeric_limits<float>::quiet_NaN(), p.return_index = 1;
    }));
    EXPECT_EQ(second.empty_frames, 1u);
    // Three of six: more than the 40 % of frames that may be empty, refused by name.
    LidarDiagnoseRunConfig cfg;
    cfg.scene = "factory_smoke";
    cfg.sensor.sensor = "vlp16";
    cfg.points = writePlantedFrames("three_empty", [](LidarFrame& f, KeyedRng&) {
        if (f.index % 2 == 1) f.points.clear();
    });
    const std::string e = test::errorOf([&] { runLidarDiagnosis(cfg); });
    EXPECT_NE(e.find("3 of its 6 frames hold no point, or points for under a tenth"), std::string::npos) << e;
}

TEST(LidarDiagnosisRun, FoldersThatAreNotTheSensorsFramesAreRefused)
{
    const std::string dir = writePlantedFrames("refused", [](LidarFrame&, KeyedRng&) {});
    LidarDiagnoseRunConfig cfg;
    cfg.scene = "factory_smoke";
    cfg.points = dir;
    // Another lidar's pattern: its frame spans another time.
    cfg.sensor.sensor = "hdl32e";
    EXPECT_NE(test::errorOf([&] { runLidarDiagnosis(cfg); }).find("where the hdl32e's frame spans"), std::string::npos);
    // The VLP-16's own frames at 20 Hz (half the columns) diagnosed as at 10 Hz; at their rate, accepted.
    cfg.sensor.sensor = "vlp16";
    cfg.points = writePlantedFrames(
        "refused_rate", [](LidarFrame&, KeyedRng&) {},
        simulateLidarRun(loadScene("factory_smoke"), "vlp16", 38, "", 20));
    EXPECT_NE(test::errorOf([&] { runLidarDiagnosis(cfg); }).find("another rate or column count"), std::string::npos);
    cfg.sensor.rate_hz = 20;
    EXPECT_EQ(runLidarDiagnosis(cfg).diagnosis.unmatched_points, 0);
    cfg.sensor.rate_hz = 0;
    // The same span and times, but each point turned 3° about z (another numbering of the
    // columns): no point lies along its beam.
    cfg.points = writePlantedFrames("refused_turned", [](LidarFrame& f, KeyedRng&) {
        const double c = std::cos(3 * kRadPerDeg), sn = std::sin(3 * kRadPerDeg);
        for (LidarPoint& p : f.points) {
            const float x = p.x, y = p.y;
            p.x = float(c * x - sn * y);
            p.y = float(sn * x + c * y);
        }
    });
    EXPECT_NE(test::errorOf([&] { runLidarDiagnosis(cfg); }).find("match no beam of the vlp16"), std::string::npos);
    // A recorded pose 0.3 m off the scene's: refused, naming the frame.
    {
        std::ifstream in(dir + "/frames.csv");
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const size_t row = text.find("\n2,") + 1,
                     x = text.find(',', text.find(',', text.find(',', text.find(',', row) + 1) + 1) + 1) + 1;
        const size_t end = text.find(',', x);
        text.replace(x, end - x, std::to_string(std::stod(text.substr(x, end - x)) + 0.3));
        std::ofstream(dir + "/frames.csv") << text;
    }
    cfg.points = dir;
    EXPECT_NE(test::errorOf([&] { runLidarDiagnosis(cfg); }).find("2.pcd: its recorded start pose is 0.3 m"),
              std::string::npos)
        << test::errorOf([&] { runLidarDiagnosis(cfg); });
    // A frame's file named longer than the file system allows: that frame named, no raw
    // std::filesystem error.
    {
        std::ifstream in(dir + "/frames.csv");
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const size_t at = text.find(",2.pcd,") + 1;
        ASSERT_NE(at, std::string::npos + 1);
        text.replace(at, 5, std::string(300, 'b'));
        std::ofstream(dir + "/frames.csv") << text;
        const std::string e = test::errorOf([&] { runLidarDiagnosis(cfg); });
        EXPECT_NE(e.find("frames.csv, frame 2 (" + std::string(300, 'b') + "): its file is missing or not a file"),
                  std::string::npos)
            << e;
    }
    // A frame of second returns alone in a strongest run: refused for its second returns, not
    // left out as empty.
    cfg.points = writePlantedFrames("second_in_strongest", [](LidarFrame& f, KeyedRng&) {
        if (f.index == 3)
            for (LidarPoint& p : f.points) p.return_index = 1;
    });
    EXPECT_NE(test::errorOf([&] {
                  runLidarDiagnosis(cfg);
              }).find("second returns, the first in " + cfg.points + "/3.pcd (--returns dual?)"),
              std::string::npos)
        << test::errorOf([&] { runLidarDiagnosis(cfg); });
    // A third return (return index 2): not a return the diagnosis reads; refused, not dropped.
    cfg.points = writePlantedFrames("refused_third", [](LidarFrame& f, KeyedRng&) {
        for (size_t i = 0; i < f.points.size(); i += 50) f.points[i].return_index = 2;
    });
    EXPECT_NE(test::errorOf([&] { runLidarDiagnosis(cfg); }).find("holds a point of return index 2"), std::string::npos)
        << test::errorOf([&] { runLidarDiagnosis(cfg); });
    // Frames with no points at all: refused by their count, before any is replayed.
    cfg.points = writePlantedFrames("refused_empty", [](LidarFrame& f, KeyedRng&) { f.points.clear(); });
    EXPECT_NE(test::errorOf([&] { runLidarDiagnosis(cfg); }).find("3 of its 6 frames (after 3 read) hold no point"),
              std::string::npos)
        << test::errorOf([&] { runLidarDiagnosis(cfg); });
    cfg.points = (scratch("lidar_diagnosis_empty")).string();
    EXPECT_NE(test::errorOf([&] { runLidarDiagnosis(cfg); }).find("frames.csv"), std::string::npos);
}
