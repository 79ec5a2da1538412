// A lidar preset's [extensions] (lidar_spec.hpp): a channel's range offset and dropout, a sector's
// dropout, simulated in the frames and read by the replay; a preset extending another by `base`.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>

#include "scene_text.hpp"
#include "scratch.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/lidar/lidar_scanner.hpp"
#include "smokescan/pipeline/lidar_diagnose_run.hpp"
#include "smokescan/scene/scene_io.hpp"

using namespace smokescan;
using namespace smokescan::test;

namespace {

/// A white wall 12 m wide and high facing the origin at x = 8 m, the sensor at the origin.
std::string wallAhead()
{
    SceneText s;
    s.raw(
        "[scene]\nname = \"wall\"\nt_start_s = 0\nt_end_s = 10\n[[materials]]\nname = \"m\"\nalbedo = [0.5, 0.5, "
        "0.5]\nnir_905 = 0.8\n");
    s.quad("wall", "m", {8, -6, -6}, {0, 12, 0}, {0, 0, 12});
    s.raw("[[sensors]]\nname = \"mount\"\ntype = \"urg04lx\"\nposition = [0, 0, 0]\n");
    return s.str();
}

/// A preset file extending the VLP-16 with `extensions` (TOML tables).
std::string extendedVlp16(const std::string& name, const std::string& extensions)
{
    const auto path = scratch("lidar_ext") / (name + ".toml");
    std::ofstream(path) << "name = \"" << name << "\"\nbase = \"vlp16\"\n" << extensions;
    return path.string();
}

struct Frames {
    std::vector<LidarFrame> frames;
    std::vector<PatternBeam> pattern;
};

Frames framesOf(const std::string& preset, int n, ReturnMode mode = ReturnMode::Strongest)
{
    const Scene scene = parseScene(wallAhead(), "test scene", ".");
    const SurfaceSet surfaces(scene);
    const LidarScanner sc(scene, surfaces, scene.sensors.front(), lidarSpec(preset), mode, 11);
    Frames f{{}, sc.pattern()};
    for (int k = 0; k < n; ++k) f.frames.push_back(sc.frame(0.1 * k, uint64_t(k)));
    return f;
}

/// Each beam's point (strongest: one at most), by beam index; null when it returned nothing.
std::vector<const LidarPoint*> byBeam(const LidarFrame& f, size_t beams)
{
    std::vector<const LidarPoint*> out(beams, nullptr);
    for (const LidarPoint& p : f.points) out[p.beam] = &p;
    return out;
}

}  // namespace

TEST(LidarExtensions, AChannelsOffsetMovesItsRangesByItAndNoOtherBeam)
{
    const std::string ext = extendedVlp16("offset", "[[extensions.channel]]\nring = 3\nrange_offset_m = 0.25\n");
    EXPECT_EQ(lidarSpec(ext).name, "offset");
    const Frames a = framesOf("vlp16", 1), b = framesOf(ext, 1);
    const auto pa = byBeam(a.frames[0], a.pattern.size()), pb = byBeam(b.frames[0], b.pattern.size());
    int moved = 0;
    for (size_t i = 0; i < pa.size(); ++i) {
        ASSERT_EQ(pa[i] == nullptr, pb[i] == nullptr) << i;  // no beam lost or gained
        if (!pa[i]) continue;
        if (a.pattern[i].channel != 3) {
            EXPECT_EQ(std::memcmp(pa[i], pb[i], sizeof(LidarPoint)), 0) << i;  // the same noise draws
            continue;
        }
        ++moved;
        EXPECT_NEAR(pb[i]->range_m - pa[i]->range_m, 0.25, 1e-5) << i;
        // Along the beam: the point moves 0.25 m in its direction, nothing across it.
        const double dx = pb[i]->x - pa[i]->x, dy = pb[i]->y - pa[i]->y, dz = pb[i]->z - pa[i]->z;
        const double ux = pa[i]->x / pa[i]->range_m, uy = pa[i]->y / pa[i]->range_m, uz = pa[i]->z / pa[i]->range_m;
        EXPECT_NEAR(dx * ux + dy * uy + dz * uz, 0.25, 1e-4) << i;
        EXPECT_NEAR(std::sqrt(dx * dx + dy * dy + dz * dz), 0.25, 1e-4) << i;
        EXPECT_EQ(pb[i]->time_s, pa[i]->time_s);
        EXPECT_EQ(pb[i]->ring, pa[i]->ring);
        EXPECT_EQ(pb[i]->intensity, pa[i]->intensity);
    }
    EXPECT_GT(moved, 200);
}

TEST(LidarExtensions, DropoutsLoseTheirShareOfBeamsWhereTheySay)
{
    // Ring 5 drops 30 %, the sector 15°…40° (to the left, +y) 50 %: where both act, 1 − 0.7·0.5 =
    // 65 %. Dual returns: a beam is lost whole or kept whole. The sector is told by where the
    // preset's own points lie (atan2 of y and x), not by the code's sector test.
    const std::string ext = extendedVlp16("drop",
                                          "[[extensions.channel]]\nring = 5\ndropout = 0.3\n"
                                          "[[extensions.sector]]\nfrom_deg = 15\nto_deg = 40\ndropout = 0.5\n");
    constexpr int kFrames = 12;
    const Frames a = framesOf("vlp16", kFrames, ReturnMode::Dual), b = framesOf(ext, kFrames, ReturnMode::Dual);
    long long n[4] = {0, 0, 0, 0}, lost[4] = {0, 0, 0, 0};
    long long ring5_pairs = 0, ring5_both = 0;  // ring 5 outside the sector: lost in frame k and k + 1
    std::vector<char> lost_before;
    for (size_t k = 0; k < a.frames.size(); ++k) {
        std::vector<int> na(a.pattern.size(), 0), nb(a.pattern.size(), 0);
        std::vector<const LidarPoint*> first(a.pattern.size(), nullptr);
        for (const LidarPoint& p : a.frames[k].points) ++na[p.beam], first[p.beam] = first[p.beam] ? first[p.beam] : &p;
        for (const LidarPoint& p : b.frames[k].points) ++nb[p.beam];
        std::vector<char> lost_now(a.pattern.size(), 0);
        for (size_t i = 0; i < na.size(); ++i) {
            ASSERT_TRUE(nb[i] == 0 || nb[i] == na[i]) << "beam " << i << " kept " << nb[i] << " of " << na[i];
            if (!na[i]) continue;
            const double az = std::atan2(first[i]->y, first[i]->x) * 180 / M_PI;
            const bool in_sector = az >= 15.1 && az < 39.9,
                       near_edge = std::abs(az - 15) < 0.1 || std::abs(az - 40) < 0.1;
            if (near_edge) continue;
            const int g = int(a.pattern[i].channel == 5) + 2 * int(in_sector);
            ++n[g];
            lost[g] += nb[i] == 0;
            lost_now[i] = nb[i] == 0;
            if (g == 1 && !lost_before.empty()) ++ring5_pairs, ring5_both += lost_now[i] && lost_before[i];
        }
        lost_before = lost_now;
    }
    EXPECT_EQ(lost[0], 0) << "beams of other rings outside the sector";
    const double want[4] = {0, 0.3, 0.5, 0.65};
    for (int g = 1; g < 4; ++g) {
        ASSERT_GT(n[g], 300) << g;
        const double share = double(lost[g]) / double(n[g]), sd = std::sqrt(want[g] * (1 - want[g]) / double(n[g]));
        EXPECT_NEAR(share, want[g], 4 * sd) << "group " << g << ": " << lost[g] << " of " << n[g];
    }
    // Each frame draws its own: a beam lost in one frame is lost in the next at the rate, 0.3² both.
    ASSERT_GT(ring5_pairs, 300);
    const double both = double(ring5_both) / double(ring5_pairs);
    EXPECT_NEAR(both, 0.09, 4 * std::sqrt(0.09 * 0.91 / double(ring5_pairs))) << ring5_both << " of " << ring5_pairs;
}

TEST(LidarExtensions, TheReplayReadsTheOffsetAndJudgesDroppingBeamsByTheirChances)
{
    const std::string ext = extendedVlp16("replay",
                                          "[[extensions.channel]]\nring = 3\nrange_offset_m = -0.1\n"
                                          "[[extensions.channel]]\nring = 5\ndropout = 0.25\n"
                                          "[[extensions.sector]]\nfrom_deg = -30\nto_deg = -20\ndropout = 0.4\n");
    const Scene scene = parseScene(wallAhead(), "test scene", ".");
    const SurfaceSet surfaces(scene);
    const LidarScanner plain(scene, surfaces, scene.sensors.front(), lidarSpec("vlp16"), ReturnMode::Strongest, 1);
    const LidarScanner extended(scene, surfaces, scene.sensors.front(), lidarSpec(ext), ReturnMode::Strongest, 1);
    const std::vector<ExpectedBeam> a = plain.expected(0), b = extended.expected(0);
    ASSERT_EQ(a.size(), b.size());
    int offset = 0, dropping = 0, in_sector = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        const int ring = plain.pattern()[i].channel;
        const double az = plain.pattern()[i].azimuth_rad * 180 / M_PI;
        if (az >= -29.9 && az < -20.1 && ring != 5 && a[i].clear) {  // the sector alone
            ++in_sector;
            EXPECT_FALSE(b[i].clear) << i;
            EXPECT_NEAR(b[i].p_none, 0.4, 1e-6) << i;
            EXPECT_NEAR(b[i].p_surface, 0.6 * a[i].p_surface, 1e-6) << i;
            continue;
        }
        if (az >= -30.1 && az < -19.9) continue;  // at the sector's edges
        if (ring == 3 && a[i].range_m > 0) {
            ++offset;
            EXPECT_NEAR(b[i].range_m - a[i].range_m, -0.1, 1e-5) << i;
            if (std::isfinite(a[i].surface_range_m))
                EXPECT_NEAR(b[i].surface_range_m - a[i].surface_range_m, -0.1, 1e-5) << i;
            EXPECT_EQ(b[i].clear, a[i].clear) << i;
        } else if (ring == 5 && a[i].clear) {
            ++dropping;
            EXPECT_FALSE(b[i].clear) << i;  // a return it may lose is judged by its chances
            EXPECT_NEAR(b[i].p_none, 0.25, 1e-6) << i;
            EXPECT_NEAR(b[i].p_surface, 0.75 * a[i].p_surface, 1e-6) << i;
        } else if (ring != 3 && ring != 5) {
            EXPECT_TRUE(a[i].range_m == b[i].range_m && a[i].clear == b[i].clear && a[i].p_none == b[i].p_none &&
                        a[i].p_surface == b[i].p_surface && a[i].surface == b[i].surface)
                << i;
        }
    }
    EXPECT_GT(offset, 150);
    EXPECT_GT(dropping, 150);
    EXPECT_GT(in_sector, 100);
}

TEST(LidarExtensions, BadExtensionsAreOneLineErrorsNamingTheKey)
{
    auto refused = [](const std::string& name, const std::string& text, const std::string& needle) {
        const auto path = scratch("lidar_ext_bad") / (name + ".toml");
        std::ofstream(path) << text;
        try {
            lidarSpec(path.string());
            ADD_FAILURE() << name << ": accepted";
        } catch (const Error& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(needle), std::string::npos) << name << ": " << what;
            EXPECT_NE(what.find(path.string()), std::string::npos) << name << ": " << what;
            EXPECT_EQ(what.find('\n'), std::string::npos) << name << ": " << what;
        }
    };
    const std::string head = "name = \"x\"\nbase = \"vlp16\"\n";
    struct Case {
        const char* name;
        std::string text;
        const char* needle;
    };
    const Case cases[] = {
        {"ring_high", head + "[[extensions.channel]]\nring = 16\ndropout = 0.1\n", "extensions.channel[0].ring"},
        {"ring_missing", head + "[[extensions.channel]]\ndropout = 0.1\n", "ring"},
        {"ring_twice", head + "[[extensions.channel]]\nring = 2\n[[extensions.channel]]\nring = 2\n", "already"},
        {"dropout_big", head + "[[extensions.channel]]\nring = 2\ndropout = 1.5\n", "dropout"},
        {"offset_nan", head + "[[extensions.channel]]\nring = 2\nrange_offset_m = nan\n", "range_offset_m"},
        {"offset_far", head + "[[extensions.channel]]\nring = 2\nrange_offset_m = 1.5\n", "range_offset_m"},
        {"sector_empty", head + "[[extensions.sector]]\nfrom_deg = 5\nto_deg = 5\ndropout = 0.2\n", "empty"},
        {"sector_180", head + "[[extensions.sector]]\nfrom_deg = 180\nto_deg = -180\ndropout = 0.2\n", "empty"},
        {"name_newline", "name = \"a\\n[x]\"\nbase = \"vlp16\"\n", "printable"},
        {"name_empty", "name = \"\"\nbase = \"vlp16\"\n", "printable"},
        {"sector_missing", head + "[[extensions.sector]]\nfrom_deg = 5\ndropout = 0.2\n", "to_deg"},
        {"sector_wide", head + "[[extensions.sector]]\nfrom_deg = -200\nto_deg = 5\ndropout = 0.2\n", "from_deg"},
        {"unknown_key", head + "[[extensions.channel]]\nring = 2\nbias = 0.1\n", "unknown key"},
        {"unknown_table", head + "[extensions]\nwindow = 1\n", "unknown key"},
        {"surface_twice",
         head +
             "[[extensions.surface]]\nname = \"a\"\nreflectance_factor = 0.5\n[[extensions.surface]]\n"
             "name = \"a\"\nreflectance_factor = 0.7\n",
         "already"},
        {"surface_unnamed", head + "[[extensions.surface]]\nreflectance_factor = 0.5\n", "name"},
        {"surface_no_factor", head + "[[extensions.surface]]\nname = \"a\"\n", "reflectance_factor"},
        {"surface_factor_0", head + "[[extensions.surface]]\nname = \"a\"\nreflectance_factor = 0\n",
         "reflectance_factor"},
        {"surface_factor_big", head + "[[extensions.surface]]\nname = \"a\"\nreflectance_factor = 20\n",
         "reflectance_factor"},
        {"surface_factor_nan", head + "[[extensions.surface]]\nname = \"a\"\nreflectance_factor = nan\n",
         "reflectance_factor"},
        {"surface_name_long",
         head + "[[extensions.surface]]\nname = \"" + std::string(4097, 'a') + "\"\nreflectance_factor = 0.5\n",
         "4096 bytes"},
        {"base_and_more", head + "columns = 512\n", "only name and [extensions]"},
        {"base_unknown", "name = \"x\"\nbase = \"vlp17\"\n", "base"},
    };
    for (const Case& c : cases) refused(c.name, c.text, c.needle);
    // A base that extends another is refused before it is read on (a preset naming itself).
    const auto self = scratch("lidar_ext_bad") / "self.toml";
    refused("self", "name = \"x\"\nbase = \"" + self.string() + "\"\n", "used as a base");
    // [extensions] belong in a preset that extends another (a whole preset is the datasheet's).
    const auto dir = scratch("lidar_ext_bad");
    std::ofstream(dir / "pattern.csv") << "0, 0, 0, 0\n10, 0, 0.01, 1\n20, 0, 0.02, 2\n";
    const std::string whole = "name = \"pf\"\npattern = \"file\"\npattern_file = \"pattern.csv\"\nrate_hz = 10\n";
    refused("whole", whole + "[[extensions.channel]]\nring = 1\ndropout = 0.1\n", "belongs in a preset that extends");
    // A base relative to the preset's own folder; a pattern file's channels bound the rings.
    std::ofstream(dir / "pf.toml") << whole;
    const auto ext = dir / "pf_ext.toml";
    std::ofstream(ext) << "name = \"pfx\"\nbase = \"pf.toml\"\n[[extensions.channel]]\nring = 2\ndropout = 0.1\n";
    EXPECT_NEAR(lidarSpec(ext.string()).extensions.dropout(2, 0), 0.1, 1e-12);
    refused("pattern_ring", "name = \"pfx\"\nbase = \"pf.toml\"\n[[extensions.channel]]\nring = 3\n", "0–2");
}

namespace {

/// Two white walls (NIR 0.8) side by side at x = 8 m: "left" (y > 0) and "right" (y < 0).
Scene twoWalls()
{
    SceneText s;
    s.raw(
        "[scene]\nname = \"walls\"\nt_start_s = 0\nt_end_s = 10\n[[materials]]\nname = \"m\"\nalbedo = [0.5, 0.5, "
        "0.5]\nnir_905 = 0.8\n");
    s.quad("left", "m", {8, 0, -6}, {0, 6, 0}, {0, 0, 12});
    s.quad("right", "m", {8, -6, -6}, {0, 6, 0}, {0, 0, 12});
    s.raw("[[sensors]]\nname = \"mount\"\ntype = \"urg04lx\"\nposition = [0, 0, 0]\n");
    return parseScene(s.str(), "test scene", ".");
}

}  // namespace

TEST(LidarExtensions, ASurfacesReflectanceFactorScalesItsEchoesAndNoOtherBeams)
{
    // The right wall at half the scene's reflectance: a Lambertian wall of NIR reflectance ρ reads
    // 100·ρ·cos θ in clear air, so the right wall 40·cos θ, the left 80·cos θ, and every beam on
    // the left is as it was, in the replay and in the frames.
    const std::string ext =
        extendedVlp16("surface", "[[extensions.surface]]\nname = \"right\"\nreflectance_factor = 0.5\n");
    const Scene scene = twoWalls();
    const SurfaceSet surfaces(scene);
    const LidarScanner plain(scene, surfaces, scene.sensors.front(), lidarSpec("vlp16"), ReturnMode::Strongest, 3);
    const LidarScanner dim(scene, surfaces, scene.sensors.front(), lidarSpec(ext), ReturnMode::Strongest, 3);
    const std::vector<ExpectedBeam> a = plain.expected(0, true), b = dim.expected(0, true);
    int on_left = 0, on_right = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        if (!a[i].clear) continue;
        const PatternBeam& pb = plain.pattern()[i];
        const double cos_t = std::cos(pb.elevation_rad) * std::cos(pb.azimuth_rad);
        if (a[i].surface == 0) {
            ++on_left;
            EXPECT_TRUE(a[i].intensity == b[i].intensity && a[i].range_m == b[i].range_m && b[i].clear) << i;
            EXPECT_NEAR(a[i].intensity, 80 * cos_t, 0.01 * 80 * cos_t) << i;
        } else if (a[i].surface == 1) {
            ++on_right;
            EXPECT_NEAR(b[i].intensity / a[i].intensity, 0.5, 1e-5) << i;
            EXPECT_NEAR(b[i].peak_sd / a[i].peak_sd, 0.5, 1e-5) << i;
            EXPECT_NEAR(b[i].intensity, 40 * cos_t, 0.01 * 40 * cos_t) << i;
            EXPECT_NEAR(b[i].peak_at_half, 0.5, 1e-4) << i;  // an echo alone: half at half the power
            EXPECT_NEAR(b[i].peak_at_quarter, 0.25, 1e-4) << i;
        }
    }
    EXPECT_GT(on_left, 2000);
    EXPECT_GT(on_right, 2000);
    const LidarFrame fa = plain.frame(0, 5), fb = dim.frame(0, 5);
    const std::vector<const LidarPoint*> pa = byBeam(fa, a.size()), pb = byBeam(fb, a.size());
    int compared = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        if (!a[i].clear || !pa[i] || !pb[i]) continue;
        ++compared;
        if (a[i].surface == 0)
            EXPECT_EQ(std::memcmp(pa[i], pb[i], sizeof(LidarPoint)), 0) << i;
        else
            EXPECT_NEAR(pb[i]->intensity / pa[i]->intensity, 0.5, 0.02) << i;
    }
    EXPECT_GT(compared, 4000);
    // A surface the scene does not have is refused when the lidar is set up in it.
    const std::string stray =
        extendedVlp16("stray", "[[extensions.surface]]\nname = \"door\"\nreflectance_factor = 0.5\n");
    try {
        LidarScanner(scene, surfaces, scene.sensors.front(), lidarSpec(stray), ReturnMode::Strongest, 3);
        ADD_FAILURE() << "a stray surface accepted";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(stray), std::string::npos) << what;
        EXPECT_NE(what.find("\"door\" is not a surface of the scene"), std::string::npos) << what;
    }
}

TEST(LidarExtensions, ASectorAcross180DegreesHoldsBothEdgesAndNothingBetween)
{
    const double d = M_PI / 180;
    const LidarSectorExtension across{170, -170, 1};  // 170°…180° and −180°…−170°
    for (double deg : {170.0, 175.0, 179.9, 180.0, -180.0, -175.0, -170.1, 185.0, -185.0, 530.0})
        EXPECT_TRUE(across.contains(deg * d)) << deg;
    for (double deg : {169.9, -170.0, -169.0, 0.0, 90.0, -90.0, 160.0, 200.0})
        EXPECT_FALSE(across.contains(deg * d)) << deg;
    const LidarSectorExtension ahead{-10, 10, 1};
    for (double deg : {-10.0, 0.0, 9.99, 350.0, -370.0}) EXPECT_TRUE(ahead.contains(deg * d)) << deg;
    for (double deg : {10.0, -10.1, 180.0, 190.0}) EXPECT_FALSE(ahead.contains(deg * d)) << deg;
    // A beam in two sectors and an extended channel keeps 1 − d of each.
    LidarExtensions e;
    e.channels.push_back({2, 0, 0.5});
    e.sectors = {ahead, {-20, 20, 0.2}};
    e.sectors[0].dropout = 0.25;
    EXPECT_NEAR(e.dropout(2, 0), 1 - 0.5 * 0.75 * 0.8, 1e-12);
    EXPECT_NEAR(e.dropout(3, 15 * d), 0.2, 1e-12);
    EXPECT_EQ(e.dropout(3, 90 * d), 0);
}

TEST(LidarExtensions, TheDiagnosisExtendsThePresetItDiagnosedByWhatItNamed)
{
    // A preset already extended (ring 2 drops 0.5, reads 0.1 m long) diagnosed again: ring 2 drops
    // another 0.2 and reads 0.05 m longer still; a window at 170°…−170° drops 0.6; ring 4's finding
    // is not named; a surface's threshold is named but is not an extension.
    const std::string had =
        extendedVlp16("had", "[[extensions.channel]]\nring = 2\nrange_offset_m = 0.1\ndropout = 0.5\n");
    const LidarSpec spec = lidarSpec(had);
    LidarDiagnosis d;
    d.verdict = "dropping_channel, window_sector, biased_channel, surface_threshold";
    d.surface_names = {"floor", "wall \"east\"\nside"};
    auto finding = [](LidarCause c, int ring, double effect, bool named) {
        LidarFinding f;
        f.cause = c, f.ring = ring, f.effect = effect, f.named = named, f.tested = true;
        return f;
    };
    d.tried = {finding(LidarCause::DroppingChannel, 2, 0.2, true), finding(LidarCause::WindowSector, -1, 0.6, true),
               finding(LidarCause::BiasedChannel, 2, 0.05, true), finding(LidarCause::BiasedChannel, 4, 0.3, false),
               finding(LidarCause::SurfaceThreshold, -1, -0.3, true)};
    d.tried[1].from_deg = 170, d.tried[1].to_deg = -170;
    d.tried[4].surface = 1;
    const std::string text = extendedLidarPreset(d, spec, "vlp16");
    const auto path = scratch("lidar_ext") / "again.toml";
    std::ofstream(path) << text;
    const LidarSpec again = lidarSpec(path.string());
    EXPECT_EQ(again.name, "had-extended");
    EXPECT_EQ(again.base, "vlp16");
    ASSERT_EQ(again.extensions.channels.size(), 1u) << text;
    EXPECT_NEAR(again.extensions.channels[0].dropout, 1 - 0.5 * 0.8, 1e-6);
    EXPECT_NEAR(again.extensions.rangeOffset_m(2), 0.15, 1e-6);
    EXPECT_EQ(again.extensions.rangeOffset_m(4), 0);
    ASSERT_EQ(again.extensions.sectors.size(), 1u) << text;
    EXPECT_EQ(again.extensions.sectors[0].from_deg, 170);
    EXPECT_EQ(again.extensions.sectors[0].to_deg, -170);
    EXPECT_NEAR(again.extensions.sectors[0].dropout, 0.6, 1e-6);
    // The surface's finding is in a comment, on one line (the surface's name holds a newline).
    EXPECT_NE(text.find("# Named but not an extension yet"), std::string::npos) << text;
    EXPECT_NE(text.find("surface_threshold (wall \"east\" side)"), std::string::npos) << text;
    // Extending it once more keeps one "-extended".
    EXPECT_EQ(lidarSpec((scratch("lidar_ext") / "again.toml").string()).name, "had-extended");
    LidarDiagnosis none;
    none.verdict = "none";
    const std::string same = extendedLidarPreset(none, again, "vlp16");
    EXPECT_NE(same.find("name = \"had-extended\"\n"), std::string::npos) << same;
}
