// 3D lidars (lidar/): patterns against the datasheets, echoes against the lidar equation, the
// motion distortion against its closed form, return modes, and point clouds read back by Open3D.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "scene_text.hpp"
#include "scratch.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/lidar/frame_pictures.hpp"
#include "smokescan/lidar/point_cloud_io.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/sensor_config/lms200.hpp"
#include "smokescan/sensor_config/urg04lx.hpp"
#include "smokescan/sensors/scanner.hpp"

using namespace smokescan;
using namespace smokescan::test;

namespace {

constexpr double kDeg = M_PI / 180;

std::string write(const std::filesystem::path& p, const std::string& text)
{
    std::ofstream(p) << text;
    return p.string();
}

/// A preset file for a patterned lidar with `beams` (azimuth_deg, elevation_deg, time_s) lines.
std::string patternedLidar(const std::string& name, const std::string& beams, const std::string& extra = "",
                           double range_sigma_m = 0.001)
{
    const auto dir = scratch("lidar_" + name);
    write(dir / "pattern.csv", "# azimuth_deg, elevation_deg, time_s\n" + beams);
    return write(dir / (name + ".toml"),
                 "name = \"" + name +
                     "\"\npattern = \"file\"\npattern_file = \"pattern.csv\"\n"
                     "wavelength_nm = 905\nrate_hz = 10\nrange_sigma_m = " +
                     tomlNumber(range_sigma_m) + "\n" + extra);
}

/// `n` beams across ±half_deg of azimuth at elevation 0, spread over the frame's first 99 ms.
std::string fan(int n, double half_deg)
{
    std::string s;
    for (int i = 0; i < n; ++i) {
        char line[96];
        std::snprintf(line, sizeof line, "%.6f, 0, %.6f\n", -half_deg + 2 * half_deg * i / (n - 1), 0.099 * i / n);
        s += line;
    }
    return s;
}

/// A wall facing the origin at x = d [m], 2h wide and high, of NIR reflectivity rho, turned by `yaw_deg` about z, with a
/// slab of grey smoke (σ_t 1/m per density, single-scattering albedo `albedo`) between x0 and x1 when density > 0.
std::string wallScene(double d, double rho, double yaw_deg = 0, double density = 0, double x0 = 4.01, double x1 = 4.51,
                      double h = 6, double albedo = 0.9)
{
    SceneText s;
    s.raw(
        "[scene]\nname = \"wall\"\nt_start_s = 0\nt_end_s = 10\n[[materials]]\nname = \"m\"\nalbedo = [0.5, 0.5, 0.5]\n"
        "nir_785 = " +
        tomlNumber(0.1 * rho) + "\nnir_905 = " + tomlNumber(rho) + "\n");
    const double c = std::cos(yaw_deg * kDeg), sn = std::sin(yaw_deg * kDeg);
    s.quad("wall", "m", {d + h * sn, -h * c, -h}, {-2 * h * sn, 2 * h * c, 0}, {0, 0, 2 * h});
    if (density > 0) s.boxSmoke({x0, -3, -3}, {x1, 3, 3}, density, 0.05, greyMedium(1.0, albedo, 0.0));
    s.raw("[[sensors]]\nname = \"mount\"\ntype = \"urg04lx\"\nposition = [0, 0, 0]\n");
    return s.str();
}

/// The scene with its sensor riding a robot "r" whose keyframes (TOML tables) are given.
std::string onRobot(std::string scene, const std::string& keyframes)
{
    scene.replace(scene.find("[[sensors]]"), std::string::npos,
                  "[[robots]]\nname = \"r\"\n" + keyframes +
                      "[[sensors]]\nname = \"mount\"\ntype = \"urg04lx\"\nrobot = \"r\"\nposition = [0, 0, 1]\n");
    return scene;
}

LidarFrame frameOf(const std::string& scene_text, const std::string& preset, ReturnMode mode, double t = 0,
                   uint64_t seed = 1)
{
    const Scene scene = parseScene(scene_text, "test scene", ".");
    const SurfaceSet surfaces(scene);
    const LidarScanner sc(scene, surfaces, scene.sensors.front(), lidarSpec(preset), mode, seed);
    return sc.frame(t, 0);
}

}  // namespace

TEST(Lidar, Vlp16PatternIsTheDatasheets)
{
    const LidarSpec s = lidarSpec("vlp16");
    ASSERT_EQ(s.channels(), 16);
    // 1808 firing cycles of 55.296 µs in a 10 Hz turn; laser n fires 2.304·n µs into its cycle.
    EXPECT_EQ(s.columns, 1808);
    const std::vector<PatternBeam> p = framePattern(s);
    ASSERT_EQ(p.size(), 1808u * 16);
    const double order[16] = {-15, 1, -13, 3, -11, 5, -9, 7, -7, 9, -5, 11, -3, 13, -1, 15};
    for (int ch = 0; ch < 16; ++ch) {
        EXPECT_NEAR(p[size_t(ch)].elevation_rad / kDeg, order[ch], 1e-12);
        EXPECT_EQ(p[size_t(ch)].channel, ch);
        EXPECT_NEAR(p[size_t(100 * 16 + ch)].time_s, 100 * 55.296e-6 + ch * 2.304e-6, 1e-12);
    }
    // The head turns clockwise at 3600°/s: the azimuth falls 0.199° a cycle, and within it.
    const double step = std::remainder(p[16].azimuth_rad - p[0].azimuth_rad, 2 * M_PI) / kDeg;
    EXPECT_NEAR(step, -3600 * 55.296e-6, 1e-9);
    EXPECT_NEAR(std::remainder(p[15].azimuth_rad - p[0].azimuth_rad, 2 * M_PI) / kDeg, -3600 * 15 * 2.304e-6, 1e-9);
    // At 20 Hz the turn holds half the cycles.
    LidarSpec fast = s;
    configureLidar(fast, 20, 0, "test", "test");
    EXPECT_EQ(fast.columns, 904);
}

TEST(Lidar, TheTwoDLasersArePlanarFansScannedAtOneInstant)
{
    // The URG-04LX's 682 steps and the LMS200's 361 half degrees as patterns: in the scan plane,
    // at the laser's own angles, all at the scan's time; the Scanner fires exactly these.
    const LrfSpec urg = urg04lx(), lms = lms200(0.5, 8);
    const std::vector<PatternBeam> u = planarFan(urg), l = planarFan(lms);
    ASSERT_EQ(u.size(), 682u);
    ASSERT_EQ(l.size(), 361u);
    EXPECT_NEAR(u.front().azimuth_rad, (44 - 384) * 2 * M_PI / 1024, 1e-12);
    EXPECT_NEAR(u.back().azimuth_rad, (725 - 384) * 2 * M_PI / 1024, 1e-12);
    EXPECT_NEAR(l.front().azimuth_rad, 0, 1e-12);
    EXPECT_NEAR(l.back().azimuth_rad, M_PI, 1e-12);
    for (const auto* fan : {&u, &l})
        for (const PatternBeam& b : *fan) {
            EXPECT_EQ(b.elevation_rad, 0);
            EXPECT_EQ(b.time_s, 0);
            EXPECT_EQ(b.channel, 0);
        }
    const Scene scene = loadScene("bocas");
    const SurfaceSet surfaces(scene);
    ScanConfig cfg;
    cfg.sensor = "urg04lx";
    const Scan scan = Scanner(scene, surfaces, cfg).scanAt(100, 0);
    ASSERT_EQ(scan.angle_rad.size(), u.size());
    for (size_t i = 0; i < u.size(); ++i) EXPECT_EQ(scan.angle_rad[i], u[i].azimuth_rad);
}

TEST(Lidar, Hdl32eAndOs1PatternsAreTheDatasheets)
{
    const LidarSpec h = lidarSpec("hdl32e");
    ASSERT_EQ(h.channels(), 32);
    EXPECT_EQ(h.columns, 2170);  // 46.08 µs cycles in 0.1 s
    std::vector<double> el;
    for (double e : h.elevation_rad) el.push_back(e / kDeg);
    std::sort(el.begin(), el.end());
    EXPECT_NEAR(el.front(), -30.67, 1e-9);
    EXPECT_NEAR(el.back(), 10.67, 1e-9);
    for (size_t i = 1; i < el.size(); ++i) EXPECT_NEAR(el[i] - el[i - 1], 1.333, 0.01);
    EXPECT_NEAR(framePattern(h)[31].time_s, 31 * 1.152e-6, 1e-12);
    // Fired interleaved, lowest first (the user manual's laser IDs 0–3).
    const double hdl_first[4] = {-30.67, -9.33, -29.33, -8.00};
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(h.elevation_rad[size_t(i)] / kDeg, hdl_first[i], 1e-9);

    const LidarSpec o = lidarSpec("os1-128");
    ASSERT_EQ(o.channels(), 128);
    EXPECT_EQ(o.columns, 1024);
    EXPECT_NEAR(o.elevation_rad.front() / kDeg, 22.5, 1e-12);
    EXPECT_NEAR(o.elevation_rad.back() / kDeg, -22.5, 1e-12);
    const std::vector<PatternBeam> p = framePattern(o);
    // A column's 128 beams fire together; columns are 1/(1024·10 Hz) apart.
    for (int ch = 0; ch < 128; ++ch) EXPECT_EQ(p[size_t(5 * 128 + ch)].time_s, p[5 * 128].time_s);
    EXPECT_NEAR(p[5 * 128].time_s, 5 / 10240.0, 1e-15);
    // The head turns clockwise (the azimuth falls column by column, 360°/1024 each) and the
    // channels' offsets stagger within a column (the preset's −4.2°, −1.4°, 1.4°, 4.2°).
    EXPECT_NEAR(std::remainder(p[128].azimuth_rad - p[0].azimuth_rad, 2 * M_PI) / kDeg, -360.0 / 1024, 1e-9);
    EXPECT_NEAR((p[1].azimuth_rad - p[0].azimuth_rad) / kDeg, 2.8, 1e-9);
    EXPECT_NEAR((p[3].azimuth_rad - p[0].azimuth_rad) / kDeg, 8.4, 1e-9);
    LidarSpec wide = o;
    configureLidar(wide, 10, 2048, "test", "test");
    EXPECT_EQ(framePattern(wide).size(), 2048u * 128);
}

TEST(Lidar, PresetsRefuseWhatTheSensorDoesNotOffer)
{
    auto refused = [](auto&& f, const std::string& needle) {
        try {
            f();
            ADD_FAILURE() << "accepted; expected " << needle;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    LidarSpec o = lidarSpec("os1-128");
    // Each error names what set the value at fault: the rate's, the columns', both for a combination.
    refused([&] { configureLidar(o, 20, 2048, "--rate", "--columns"); },
            "--rate and --columns: the os1-128 fires at most 20480 columns a second");
    refused([&] { configureLidar(o, 15, 0, "--rate", "--columns"); }, "--rate: the os1-128 spins at 10, 20 Hz, not 15");
    refused([&] { configureLidar(o, 10, 1000, "--rate", "--columns"); },
            "--columns: the os1-128 offers 512, 1024, 2048 columns");
    refused([&] { configureLidar(o, 0, 8192, "--rate", "--columns"); },
            "--columns: the os1-128 offers 512, 1024, 2048 columns, not 8192");
    LidarSpec v = lidarSpec("vlp16");
    refused(
        [&] { configureLidar(v, 10, 1024, "--rate", "--columns"); },
        "--columns: the vlp16's columns follow from its rate (a column each firing cycle): 1808 at 10 Hz, not 1024");
    configureLidar(v, 20, 904, "--rate", "--columns");  // the column count its rate gives: accepted
    EXPECT_EQ(v.columns, 904);
    refused([] { lidarSpec("vlp32"); }, "no lidar preset 'vlp32' (presets: hdl32e, os1-128, vlp16");
    refused([] { parseReturnMode("both", "--returns"); }, "unknown return mode 'both'");
    const Scene scene = parseScene(wallScene(5, 0.5), "s", ".");
    const SurfaceSet surfaces(scene);
    refused([&] { LidarScanner(scene, surfaces, scene.sensors.front(), lidarSpec("os1-128"), ReturnMode::Last, 1); },
            "offers strongest, dual, not last");
    // A preset file's bad keys name the file, its line and the key: {file, keys after name and
    // pattern, what the error says}.
    const auto dir = scratch("lidar_bad_presets");
    const std::string head = "name = \"x\"\npattern = \"spinning\"\n";
    const std::array<std::array<const char*, 3>, 13> bad = {{
        {"a.toml", "elevation_deg = [0, 1]\nfire_offset_us = [0]\n",
         "a.toml:4: fire_offset_us must have one value per channel (2)"},
        {"b.toml", "elevation_deg = [0]\ncolour = 3\n", "unknown key 'colour': not a key of a lidar preset"},
        {"c.toml", "elevation_uniform_deg = [1, -1, 512]\ncolumns = 8192\n",
         "would fire more than 4,000,000 beams a frame"},
        {"d.toml", "elevation_deg = [0]\nmax_echoes = 9\n", "max_echoes must be 1–8"},
        {"e.toml", "elevation_deg = [0]\nmax_echoes = 4294967299\n", "max_echoes must be 1–8"},
        {"f.toml", "elevation_deg = [0]\ncolumns = 4294967808\n", "columns must be 1–8192"},
        {"g.toml", "elevation_deg = [0]\ncolumns = 256\ncolumns_allowed = [512]\n",
         "columns must be one of columns_allowed"},
        {"h.toml", "elevation_deg = [0]\ncolumns_allowed = [1024, 1024.7]\n",
         "columns_allowed must hold whole column counts"},
        {"i.toml", "elevation_deg = [0, 1]\nfire_offset_us = [0, 1e9]\n",
         "fire up to 1000000000 us into a column of 97.65625 us"},
        {"j.toml", "elevation_deg = [0, 1]\nfire_offset_us = [0, -1]\n", "fire_offset_us must not be negative"},
        {"k.toml", "elevation_deg = [0]\nrates_hz = [10, 0.001]\n", "rates_hz must hold rates in [0.01, 100] Hz"},
        {"l.toml", "elevation_deg = [0]\nazimuth_offset_deg = [1e300]\n", "azimuth_offset_deg must lie within ±360°"},
        {"m.toml", "elevation_uniform_deg = [100, -10, 3]\n", "m.toml:3: elevation_uniform_deg must lie within ±90°"},
    }};
    for (const auto& row : bad) refused([&] { lidarSpec(write(dir / row[0], head + row[1])); }, row[2]);
    // A combination the sensor cannot fire, set by one option: that option named alone.
    LidarSpec many = lidarSpec(write(dir / "many.toml",
                                     head +
                                         "elevation_uniform_deg = [-10, 10, 512]\ncolumns = 1024\n"
                                         "columns_allowed = [1024, 8192]\n"));
    refused([&] { configureLidar(many, 0, 8192, "--rate", "--columns"); },
            "--columns: the x would fire more than 4,000,000 beams a frame");
    LidarSpec fast = lidarSpec(write(dir / "fast.toml",
                                     head +
                                         "elevation_deg = [0]\ncolumns = 2048\nrates_hz = [10, 20]\n"
                                         "max_column_rate_hz = 20480\n"));
    refused([&] { configureLidar(fast, 20, 0, "--rate", "--columns"); },
            "--rate: the x fires at most 20480 columns a second");
    // A pattern timed for 10 Hz cannot run at 20 Hz: its beams would leave the frame.
    LidarSpec slow = lidarSpec(patternedLidar("slow", "0, 0, 0\n1, 0, 0.08\n", "rates_hz = [10, 20]\n"));
    refused([&] { configureLidar(slow, 20, 0, "--rate", "--columns"); },
            "--rate: the slow's pattern fires until 0.08 s, beyond a frame of 0.05 s at 20 Hz");
}

TEST(Lidar, PatternFileBadLinesAreRefusedWithTheirLine)
{
    auto refused = [](const std::string& beams, const std::string& needle) {
        try {
            lidarSpec(patternedLidar("bad", beams));
            ADD_FAILURE() << "accepted; expected " << needle;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    refused("0, 0, 0\n1, nan, 0.01\n", "pattern.csv:3: elevation_deg 'nan' is not a finite number");
    refused("0, 0, 0.01\n1, 0, 0.01\n", "pattern.csv:3: time_s must increase from line to line");
    refused("0, 0, 0.02\n1, 0, 0.01\n", "pattern.csv:3: time_s must increase");
    refused("0, 0, 0.1\n", "pattern.csv:2: time_s must lie within the frame [0, 0.1");
    refused("0, 0\n", "pattern.csv:2: expected azimuth_deg, elevation_deg, time_s[, channel]");
    refused("0, 95, 0\n", "elevation_deg must lie within ±90");
    refused("0, 0, 0, 1.5\n", "channel must be an integer");
    refused("# nothing\n", "the pattern file has no beams");
    refused("0, 0, 0,\n", "pattern.csv:2: ends with a comma (an empty field)");
    refused("0x10, 0, 0\n", "pattern.csv:2: azimuth_deg '0x10' is not a decimal number");
    // A byte-order mark is skipped and an underflowing time is its tiny value, not an error.
    const auto bom = scratch("lidar_bom") / "beams.csv";
    write(bom,
          "\xEF\xBB\xBF"
          "0, 0, 0\n1, 0, 1e-310\n");
    const std::vector<PatternBeam> read = readPatternFile(bom.string(), 0.1);
    ASSERT_EQ(read.size(), 2u);
    EXPECT_GT(read[1].time_s, 0.0);
    EXPECT_LT(read[1].time_s, 1e-300);
    const auto empty = scratch("lidar_empty") / "e.toml";
    write(empty, "name = \"e\"\npattern = \"file\"\npattern_file = \"\"\n");
    try {
        lidarSpec(empty.string());
        ADD_FAILURE() << "an empty pattern_file was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("e.toml:3: pattern_file is empty"), std::string::npos) << e.what();
    }
}

TEST(Lidar, ReturnModesPickTheirEchoes)
{
    // Echoes in range order: a weak smoke echo, the strongest, a weaker last one.
    std::vector<LidarEcho> e(3);
    e[0].peak = 0.2, e[1].peak = 0.9, e[2].peak = 0.5;
    using V = std::vector<size_t>;
    EXPECT_EQ(selectReturns(e, ReturnMode::First, false), V{0});
    EXPECT_EQ(selectReturns(e, ReturnMode::Last, false), V{2});
    EXPECT_EQ(selectReturns(e, ReturnMode::Strongest, false), V{1});
    EXPECT_EQ(selectReturns(e, ReturnMode::Dual, false), (V{1, 2}));  // strongest and last
    EXPECT_EQ(selectReturns(e, ReturnMode::Dual, true), (V{1, 2}));  // strongest and second strongest
    e[2].peak = 0.95;  // the last is the strongest: Velodyne's dual gives the second strongest beside it
    EXPECT_EQ(selectReturns(e, ReturnMode::Dual, false), (V{1, 2}));
    e[0].peak = 0.6;
    EXPECT_EQ(selectReturns(e, ReturnMode::Dual, true), (V{1, 2}));
    // Where the two duals differ: the strongest in the middle, a weaker first and a weakest last.
    e = std::vector<LidarEcho>(3);
    e[0].peak = 0.5, e[1].peak = 0.9, e[2].peak = 0.2;
    EXPECT_EQ(selectReturns(e, ReturnMode::Dual, false), (V{1, 2}));  // Velodyne: strongest and last
    EXPECT_EQ(selectReturns(e, ReturnMode::Dual, true), (V{0, 1}));  // Ouster: strongest and second strongest
    e.resize(1);
    EXPECT_EQ(selectReturns(e, ReturnMode::Dual, false), V{0});
    EXPECT_TRUE(selectReturns({}, ReturnMode::Strongest, false).empty());
}

TEST(Lidar, IntensityIsTheCalibratedReflectivityOfALambertianTarget)
{
    // 100·ρ·cos θ at any range in clear air (the lidar equation with the R² taken out), ρ the
    // reflectance in the lidar's band (905 nm here: the wall's 785 nm value is a tenth of it).
    const std::string preset = patternedLidar("flat", fan(21, 1.0));
    // The receiver noise as docs/lidar.md states it: 0.1/(50² · (6 + 1.2816)), the default range
    // at which a 10 % target is detected and the threshold.
    const double noise = 0.1 / (50.0 * 50.0) / (6 + 1.2816);
    EXPECT_NEAR(lidarSpec(preset).receiver.noise_floor, noise, 1e-12);
    for (double rho : {0.2, 0.8})
        for (double d : {5.0, 20.0})
            for (double yaw : {0.0, 60.0}) {
                const LidarFrame f = frameOf(wallScene(d, rho, yaw), preset, ReturnMode::Strongest);
                ASSERT_EQ(f.points.size(), 21u);
                for (const LidarPoint& p : f.points) {
                    // The incidence is the wall's turn less the beam's azimuth; the tolerance is
                    // four times the receiver noise over the echo's peak, and the sampling's 1 %.
                    const double cos_i = std::cos(yaw * kDeg - std::atan2(p.y, p.x)), peak = rho * cos_i / (d * d);
                    EXPECT_NEAR(p.intensity, 100 * rho * cos_i, 100 * rho * cos_i * (0.01 + 4 * noise / peak))
                        << d << " " << yaw;
                    EXPECT_EQ(p.source, uint8_t(EchoSource::Surface));
                }
            }
    // Within the receiver's overlap (it rises from 0.05 to 0.3 m) the intensity is still the
    // reflectance: the lidar's calibration divides the overlap out. (A pulse short enough to
    // resolve 0.2 m: a 5 ns pulse's half width is 0.37 m, inside which the leading edge is lost.)
    const std::string near = patternedLidar("near", fan(5, 1.0), "range_min_m = 0.1\npulse_fwhm_ns = 0.5\n");
    const LidarFrame f = frameOf(wallScene(0.2, 0.5), near, ReturnMode::Strongest);
    ASSERT_EQ(f.points.size(), 5u);
    for (const LidarPoint& p : f.points) {
        EXPECT_NEAR(p.x, 0.2, 0.005);
        EXPECT_NEAR(p.intensity, 50, 1.0);
    }
}

namespace {

/// The echo of a uniform slab of smoke from s0 to s1 along a beam [m], extinction sigma [1/m],
/// backscatter beta [1/(m·sr)], seen through a Gaussian pulse of σ sigma_p [m], worked out here
/// on a fine grid apart from the receiver's code: the waveform ∫ π·β·e^(−2σ(r − s0))/r² ·
/// e^(−(x − r)²/2σ_p²) dr, its peak, and the range the receiver's rule gives (the half-maximum
/// leading edge plus half the pulse's width) with the intensity 100·peak·R².
std::pair<double, double> slabEcho(double s0, double s1, double sigma, double beta, double sigma_p)
{
    const double dr = 1e-3, dx = 2e-3;
    double peak = 0;
    std::vector<std::pair<double, double>> w;
    for (double x = s0 - 5 * sigma_p; x < s1 + 5 * sigma_p; x += dx) {
        double sum = 0;
        for (double r = s0 + 0.5 * dr; r < s1; r += dr)
            sum += M_PI * beta * std::exp(-2 * sigma * (r - s0)) / (r * r) *
                std::exp(-(x - r) * (x - r) / (2 * sigma_p * sigma_p)) * dr;
        w.emplace_back(x, sum);
        peak = std::max(peak, sum);
    }
    size_t i = 0;
    while (w[i].second < 0.5 * peak) ++i;
    const double lead = w[i - 1].first + dx * (0.5 * peak - w[i - 1].second) / (w[i].second - w[i - 1].second);
    const double range = lead + std::sqrt(2 * std::log(2.0)) * sigma_p;
    return {range, 100 * peak * range * range};
}

}  // namespace

TEST(Lidar, AFogSlabBeforeAWallGivesTwoEchoesAttenuatedByTheLidarEquation)
{
    // A slab of optical depth τ = σ_t·ρ·0.5 m at 4.025–4.525 m (ten voxels of 5 cm whose centres
    // lie in the box 4.01–4.51) before a wall at 10 m: its own echo first, at the range and with
    // the intensity its backscatter gives (slabEcho), then the wall's at 10 m with its intensity
    // times T² = e^(−2τ/cos a) for a beam at azimuth a. Beams over ±25°, where 1/cos a matters.
    const std::string preset = patternedLidar("slab", fan(41, 25.0));
    const double sigma_p = 299792458.0 * 5e-9 / 2 / (2 * std::sqrt(2 * std::log(2.0)));  // 5 ns pulse
    const double beta = 0.8 * 0.9 / (4 * M_PI);  // σ_t·albedo·p(π), isotropic (g = 0)
    const double density = 0.8, tau = 1.0 * density * 0.5;
    const LidarFrame clear = frameOf(wallScene(10, 0.8), preset, ReturnMode::Dual);
    const LidarFrame fog = frameOf(wallScene(10, 0.8, 0, density), preset, ReturnMode::Dual);
    const LidarFrame first = frameOf(wallScene(10, 0.8, 0, density), preset, ReturnMode::First);
    const LidarFrame last = frameOf(wallScene(10, 0.8, 0, density), preset, ReturnMode::Last);
    ASSERT_EQ(clear.points.size(), 41u);  // one echo a beam: one point
    ASSERT_EQ(fog.points.size(), 82u);
    ASSERT_EQ(first.points.size(), 41u);
    ASSERT_EQ(last.points.size(), 41u);
    double worst_range = 0, worst_intensity = 0;
    for (size_t i = 0; i < 41; ++i) {
        const LidarPoint &smoke = fog.points[2 * i], &wall = fog.points[2 * i + 1];
        EXPECT_EQ(smoke.source, uint8_t(EchoSource::Smoke));
        EXPECT_EQ(wall.source, uint8_t(EchoSource::Surface));
        const double c = std::cos(std::atan2(wall.y, wall.x));
        const auto [range, intensity] = slabEcho(4.025 / c, 4.525 / c, 0.8, beta, sigma_p);
        // The receiver sums the smoke onto points a quarter of the pulse's σ apart (8 cm), each
        // piece of the path shared between the two around it: within 1 cm and 2 % (seen: 4.9 mm
        // and 0.8 %).
        EXPECT_NEAR(smoke.range_m, range, 0.01);
        EXPECT_NEAR(smoke.intensity, intensity, 0.02 * intensity);
        worst_range = std::max(worst_range, std::abs(smoke.range_m - range));
        worst_intensity = std::max(worst_intensity, std::abs(smoke.intensity / intensity - 1));
        EXPECT_NEAR(wall.range_m * c, 10.0, 0.005);  // 5 σ of the range noise
        // Noise: the intensities' ratio to 0.4 % (each peak is ~400 σ of the receiver's noise).
        EXPECT_NEAR(wall.intensity / clear.points[i].intensity, std::exp(-2 * tau / c), 0.004);
        EXPECT_EQ(smoke.return_index, 0);
        EXPECT_EQ(wall.return_index, 1);
        EXPECT_FLOAT_EQ(first.points[i].range_m, smoke.range_m);
        EXPECT_FLOAT_EQ(last.points[i].range_m, wall.range_m);
    }
    std::printf("the slab's echo against the integral: range within %.1f mm, intensity within %.2f %%\n",
                1e3 * worst_range, 100 * worst_intensity);
}

TEST(Lidar, AMovingLidarsPointsFollowTheClosedFormOfItsMotion)
{
    // The robot drives at 2 m/s towards a wall at x = 30 m; a beam fired at scene time t sees the
    // wall at x = 30 − 2t in the sensor's frame at that instant, whatever its azimuth (a thin beam:
    // a wide footprint on an oblique wall reads nearer, as real ones do; a quiet receiver: its
    // leading-edge jitter aside).
    const std::string scene = onRobot(wallScene(30, 0.8, 0, 0, 0, 0, 40),
                                      "[[robots.keyframes]]\ntime_s = 0\nposition = [0, 0, 0]\n"
                                      "[[robots.keyframes]]\ntime_s = 10\nposition = [20, 0, 0]\n");
    const LidarFrame f =
        frameOf(scene, patternedLidar("moving", fan(200, 40), "divergence_mrad = 0.01\nrange_at_10pct_m = 5000\n"),
                ReturnMode::Strongest, 2.0);
    ASSERT_EQ(f.points.size(), 200u);
    EXPECT_NEAR(f.start_pose.t.x(), 4.0, 1e-9);
    EXPECT_NEAR(f.end_pose.t.x(), 4.0 + 2 * 0.099 * 199 / 200, 1e-9);
    double spread = 0;
    for (const LidarPoint& p : f.points) {
        EXPECT_NEAR(p.x, 30 - 2 * (2.0 + p.time_s), 0.005) << p.time_s;  // 5 σ of the range noise
        spread = std::max(spread, double(std::abs(p.x - f.points.front().x)));
    }
    EXPECT_GT(spread, 0.19);  // the distortion is there to see: 0.2 m over the frame
}

TEST(Lidar, ATurningLidarsPointsFollowTheClosedFormOfItsTurn)
{
    // The robot turns on the spot at 9°/s before a wall at x = 20 m: a beam at azimuth α fired at
    // scene time t leaves along α + ψ(t), ψ = 9°/s · t, and is written in the sensor's frame of
    // that instant: at range 20/cos(α + ψ), at (r·cos α, r·sin α).
    const std::string scene = onRobot(wallScene(20, 0.8, 0, 0, 0, 0, 40),
                                      "[[robots.keyframes]]\ntime_s = 0\nposition = [0, 0, 0]\nyaw_deg = 0\n"
                                      "[[robots.keyframes]]\ntime_s = 10\nposition = [0, 0, 0]\nyaw_deg = 90\n");
    const std::string preset =
        patternedLidar("turning", fan(200, 30), "divergence_mrad = 0.01\nrange_at_10pct_m = 5000\n");
    const LidarFrame f = frameOf(scene, preset, ReturnMode::Strongest, 2.0);
    ASSERT_EQ(f.points.size(), 200u);
    const std::vector<PatternBeam> beams = framePattern(lidarSpec(preset));
    for (const LidarPoint& p : f.points) {
        const double alpha = beams[p.beam].azimuth_rad, psi = 9 * kDeg * (2.0 + p.time_s);
        const double r = 20 / std::cos(alpha + psi);
        EXPECT_NEAR(p.x, r * std::cos(alpha), 0.006) << p.time_s;  // 5 σ of the range noise, and more
        EXPECT_NEAR(p.y, r * std::sin(alpha), 0.006) << p.time_s;
    }
    // The frame's poses: 18° at its start, 18.9° at its last beam.
    EXPECT_NEAR(std::atan2(f.start_pose.R(1, 0), f.start_pose.R(0, 0)) / kDeg, 18, 1e-6);
    EXPECT_NEAR(std::atan2(f.end_pose.R(1, 0), f.end_pose.R(0, 0)) / kDeg, 9 * (2.0 + 0.099 * 199 / 200), 1e-6);
    // frames.csv's line: the times, and the poses as quaternions about z (qw = cos ψ/2, qz = sin ψ/2).
    std::vector<double> v;
    std::istringstream row(frameIndexRow(f, "000000.pcd"));
    for (std::string cell; std::getline(row, cell, ',');)
        if (cell != "000000.pcd") v.push_back(std::stod(cell));
    ASSERT_EQ(v.size(), 17u);  // frame, start_s, end_s, 7 + 7 pose values
    EXPECT_EQ(v[1], 2.0);
    EXPECT_NEAR(v[2], 2.0 + 0.099 * 199 / 200, 1e-9);
    const double psi0 = 18 * kDeg, psi1 = 9 * kDeg * (2.0 + 0.099 * 199 / 200);
    EXPECT_NEAR(v[6], std::cos(psi0 / 2), 1e-8);
    EXPECT_NEAR(v[9], std::sin(psi0 / 2), 1e-8);
    EXPECT_NEAR(v[13], std::cos(psi1 / 2), 1e-8);
    EXPECT_NEAR(v[16], std::sin(psi1 / 2), 1e-8);
    EXPECT_EQ(frameIndexHeader().substr(0, 40), "frame,file,start_s,end_s,start_x_m,start");
}

TEST(Lidar, AReceiverResolvesAtMostItsMaxEchoes)
{
    // Two slabs (4–4.5 m and 7–7.5 m, far enough apart that their echoes do not merge) before a
    // wall at 12 m: three echoes. A receiver that resolves two keeps the nearer two, so its last
    // return is the second slab, not the wall.
    std::string scene = wallScene(12, 0.8, 0, 0.8);
    scene +=
        "[[smoke]]\nname = \"second\"\ntype = \"box\"\nmin = [7.01, -3, -3]\nmax = [7.51, 3, 3]\nvoxel = 0.05\n"
        "density = 0.8\nmedium = " +
        greyMedium(1.0, 0.9, 0.0) + "\n";
    const LidarFrame three = frameOf(scene, patternedLidar("three", fan(11, 2.0)), ReturnMode::Last);
    const LidarFrame two = frameOf(scene, patternedLidar("two", fan(11, 2.0), "max_echoes = 2\n"), ReturnMode::Last);
    ASSERT_EQ(three.points.size(), 11u);
    ASSERT_EQ(two.points.size(), 11u);
    for (size_t i = 0; i < 11; ++i) {
        EXPECT_NEAR(three.points[i].x, 12.0, 0.01);
        EXPECT_EQ(three.points[i].source, uint8_t(EchoSource::Surface));
        EXPECT_NEAR(two.points[i].x, 7.2, 0.2);  // the second slab's echo
        EXPECT_EQ(two.points[i].source, uint8_t(EchoSource::Smoke));
    }
}

TEST(Lidar, APatternFilesBeamsGoWhereTheFileSends)
{
    // A beam at azimuth 30°, elevation 10° meets the wall x = 5 m at y = 5·tan 30°,
    // z = 5·tan 10°/cos 30°; its fourth column is its ring.
    const std::string preset = patternedLidar("aimed", "30, 10, 0, 7\n-20, -5, 0.01, 3\n", "divergence_mrad = 0.01\n");
    const LidarFrame f = frameOf(wallScene(5, 0.8), preset, ReturnMode::Strongest);
    ASSERT_EQ(f.points.size(), 2u);
    EXPECT_NEAR(f.points[0].x, 5, 0.005);
    EXPECT_NEAR(f.points[0].y, 5 * std::tan(30 * kDeg), 0.005);
    EXPECT_NEAR(f.points[0].z, 5 * std::tan(10 * kDeg) / std::cos(30 * kDeg), 0.005);
    EXPECT_EQ(f.points[0].ring, 7);
    EXPECT_NEAR(f.points[1].y, -5 * std::tan(20 * kDeg), 0.005);
    EXPECT_NEAR(f.points[1].z, -5 * std::tan(5 * kDeg) / std::cos(20 * kDeg), 0.005);
    EXPECT_EQ(f.points[1].ring, 3);
    EXPECT_FLOAT_EQ(f.points[1].time_s, 0.01f);
}

TEST(Lidar, TheReceiversNoiseAndDetectionAreTheStatedOnes)
{
    // 400 beams on a wall: the ranges scatter with the preset's range σ (the leading edge's own
    // jitter is ~1 % of it at this signal), its standard error 3.5 %.
    const std::string noisy = patternedLidar("noisy", fan(400, 1.0), "", 0.02);
    const LidarFrame f = frameOf(wallScene(10, 0.8), noisy, ReturnMode::Strongest, 0, 11);
    ASSERT_EQ(f.points.size(), 400u);
    double ss = 0;
    for (const LidarPoint& p : f.points) ss += std::pow(double(p.x) - 10.0, 2);
    EXPECT_NEAR(std::sqrt(ss / 400), 0.02, 0.02 * 0.12);
    // A 10 % target at range_at_10pct_m (50 m by default) is detected at least 90 % of the time
    // (binomial: 3 σ below 0.9 is 0.855 over 400 beams); at 0.8 of it nearly always, at 1.3 of it
    // (its peak 4.3 σ of noise against a threshold of 6) seldom.
    auto detected = [&](double d) {
        const LidarFrame g = frameOf(wallScene(d, 0.1), noisy, ReturnMode::Strongest, 0, 12);
        return double(g.points.size()) / 400;
    };
    EXPECT_GE(detected(50), 0.855);
    EXPECT_GE(detected(40), 0.99);
    EXPECT_LE(detected(65), 0.3);
}

TEST(Lidar, FramesDoNotDependOnTheThreadCount)
{
    const std::string scene = wallScene(10, 0.8, 20, 0.8);
    auto frame = [&](int threads) {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, size_t(threads));
        return frameOf(scene, "vlp16", ReturnMode::Dual, 0, 7);
    };
    const LidarFrame a = frame(1), b = frame(2);
    ASSERT_EQ(a.points.size(), b.points.size());
    ASSERT_GT(a.points.size(), 1000u);
    for (size_t i = 0; i < a.points.size(); ++i)
        ASSERT_EQ(std::memcmp(&a.points[i], &b.points[i], sizeof(LidarPoint)), 0) << i;
    // Another seed draws other noise on the same geometry: the same wall, other ranges.
    const std::string clear = wallScene(10, 0.8, 20);
    const LidarFrame c = frameOf(clear, "vlp16", ReturnMode::Strongest, 0, 8);
    const LidarFrame d = frameOf(clear, "vlp16", ReturnMode::Strongest, 0, 7);
    ASSERT_EQ(c.points.size(), d.points.size());
    int differ = 0;
    for (size_t i = 0; i < c.points.size(); ++i) {
        differ += c.points[i].range_m != d.points[i].range_m;
        EXPECT_NEAR(c.points[i].range_m, d.points[i].range_m, 0.2) << i;  // within the noise
    }
    EXPECT_GT(differ, int(c.points.size()) * 9 / 10);
}

TEST(Lidar, RangeImagePutsAheadInTheMiddleAndTopViewPutsPointsWhereTheyAre)
{
    // A wall 5 m ahead, nothing behind: the range image is lit around its middle column only, and
    // the top view marks the wall's line x = 5 m.
    const LidarFrame f = frameOf(wallScene(5, 0.8), "os1-128", ReturnMode::Strongest);
    const Image im = rangeImage(f, lidarSpec("os1-128"), 0);
    ASSERT_EQ(im.width, 1024);
    ASSERT_EQ(im.height, 256);  // 128 rows, each twice
    const int mid_row = im.height / 2;
    EXPECT_GT(im.at(512, mid_row, 0), 0.1f);  // straight ahead
    EXPECT_EQ(im.at(0, mid_row, 0), 0.0f);  // straight behind
    EXPECT_EQ(im.at(256, mid_row, 0), 0.0f);  // to the left: the wall ends at ±50°
    // The frame's own range image (channels × columns, in firing order) holds each beam's first
    // kept range.
    ASSERT_EQ(f.range_image.size(), size_t(128 * 1024));
    for (const LidarPoint& p : f.points)
        EXPECT_EQ(f.range_image[size_t(p.ring) * 1024 + p.beam / 128], p.range_m) << p.beam;
    const Image top = topView(f, 10, 200);  // 10 px a metre, the sensor at (100, 100)
    EXPECT_LT(top.at(150, 100, 0), 0.5f);  // a grey point on the wall at x = 5 m
    EXPECT_EQ(top.at(50, 100, 0), 1.0f);  // nothing behind
    EXPECT_THROW(rangeImage(f, lidarSpec(patternedLidar("flat2", fan(3, 1.0))), 0), Error);

    // A wall along the left (y = +3 m) above the sensor (z from 0 to 3 m): lit on the left half
    // of the range image only, in the VLP-16's upper rows only (rows by elevation, not by firing
    // order), and above the sensor's row in the top view.
    SceneText left;
    left.raw("[scene]\nname = \"left\"\n[[materials]]\nname = \"m\"\nnir_905 = 0.8\n");
    left.quad("wall", "m", {-20, 3, 0.01}, {40, 0, 0}, {0, 0, 3});
    left.raw("[[sensors]]\nname = \"mount\"\ntype = \"urg04lx\"\nposition = [0, 0, 0]\n");
    const LidarFrame v = frameOf(left.str(), "vlp16", ReturnMode::Strongest);
    const Image vi = rangeImage(v, lidarSpec("vlp16"), 0);
    const int rep = vi.height / 16, quarter = vi.width / 4;
    for (int row = 0; row < 16; ++row) {
        const bool up = row < 8;  // elevations +15 … +1 on top
        EXPECT_EQ(vi.at(quarter, row * rep, 0) > 0, up) << "row " << row;  // 90° to the left
        EXPECT_EQ(vi.at(3 * quarter, row * rep, 0), 0.0f) << "row " << row;  // 90° to the right
    }
    const Image vt = topView(v, 10, 200);
    EXPECT_LT(vt.at(100, 70, 0), 0.5f);  // y = +3 m: 30 px above the sensor
    EXPECT_EQ(vt.at(100, 130, 0), 1.0f);
}

namespace {

/// Open3D's values of each field of a point cloud file, or empty when Debian's python3-open3d is
/// missing.
std::map<std::string, std::vector<double>> readWithOpen3d(const std::string& path)
{
    const std::string cmd =
        "/usr/bin/python3 " SMOKESCAN_SOURCE_DIR "/tests/python/read_cloud.py " + path + " 2>/dev/null";
    std::map<std::string, std::vector<double>> out;
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return out;
    std::string text;
    char buf[65536];
    for (size_t n; (n = fread(buf, 1, sizeof buf, p)) > 0;) text.append(buf, n);
    if (pclose(p) != 0) return {};
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
        std::istringstream in(line);
        std::string name;
        in >> name;
        for (double v; in >> v;) out[name].push_back(v);
    }
    return out;
}

}  // namespace

TEST(Lidar, PcdAndPlyFramesAreReadBackFieldByFieldByOpen3d)
{
    if (std::system("/usr/bin/python3 -c 'import open3d' >/dev/null 2>&1") != 0)
        GTEST_SKIP() << "Debian's python3-open3d is not installed (scripts/setup.sh installs it)";
    const LidarFrame f = frameOf(wallScene(10, 0.8, 20, 0.8), "vlp16", ReturnMode::Dual, 0, 3);
    ASSERT_GT(f.points.size(), 1000u);
    const auto dir = scratch("lidar_open3d");
    for (const std::string ext : {"pcd", "ply"}) {
        const std::string path = (dir / ("frame." + ext)).string();
        (ext == "pcd" ? writePcd : writePly)(path, f);
        const auto v = readWithOpen3d(path);
        ASSERT_EQ(v.count("positions"), 1u) << ext;
        const size_t n = f.points.size();
        ASSERT_EQ(v.at("positions").size(), 3 * n) << ext;
        for (const char* k : {"intensity", "ring", "return_index", "time", "source"})
            ASSERT_EQ(v.at(k).size(), n) << ext << " " << k;
        for (size_t i = 0; i < n; ++i) {
            const LidarPoint& p = f.points[i];
            ASSERT_EQ(v.at("positions")[3 * i], double(p.x)) << ext << i;
            ASSERT_EQ(v.at("positions")[3 * i + 1], double(p.y));
            ASSERT_EQ(v.at("positions")[3 * i + 2], double(p.z));
            ASSERT_EQ(v.at("intensity")[i], double(p.intensity));
            ASSERT_EQ(v.at("ring")[i], double(p.ring));
            ASSERT_EQ(v.at("return_index")[i], double(p.return_index));
            ASSERT_EQ(v.at("time")[i], double(p.time_s));
            ASSERT_EQ(v.at("source")[i], double(p.source));
        }
    }
}

namespace {

void expectRefused(const std::string& bytes, const std::string& needle)
{
    try {
        parsePointCloud(bytes, "bad.pcd");
        ADD_FAILURE() << "accepted; expected " << needle;
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
}

const char* kPcdHeader = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n";

}  // namespace

TEST(Lidar, FramesWrittenAreReadBackFieldByFieldWithTheirTimeAndPose)
{
    // A turning robot before a fog slab and a wall, dual returns: points from smoke and from the
    // wall, both return indexes, firing times across the frame, a pose that is not the identity.
    const std::string scene = onRobot(wallScene(10, 0.8, 0, 0.8),
                                      "[[robots.keyframes]]\ntime_s = 0\nposition = [1, 2, 0]\nyaw_deg = 0\n"
                                      "[[robots.keyframes]]\ntime_s = 10\nposition = [1, 2, 0]\nyaw_deg = 90\n");
    const LidarFrame f = frameOf(scene, patternedLidar("readback", fan(41, 25.0)), ReturnMode::Dual, 2.0);
    std::set<int> kinds;  // (source, return index) pairs seen
    for (const LidarPoint& p : f.points) kinds.insert(10 * p.source + p.return_index);
    ASSERT_GT(f.points.size(), 41u);
    EXPECT_EQ(kinds, (std::set<int>{0, 1, 10}));  // surface first or second, smoke first
    const auto dir = scratch("lidar_readback");
    writePcd((dir / "f.pcd").string(), f);
    writePly((dir / "f.ply").string(), f);
    for (const char* name : {"f.pcd", "f.ply"}) {
        const PointCloudFile r = readPointCloud((dir / name).string());
        ASSERT_EQ(r.points.size(), f.points.size()) << name;
        EXPECT_EQ(r.skipped, 0u);
        EXPECT_EQ(r.fields,
                  (std::vector<std::string>{"x", "y", "z", "intensity", "ring", "return_index", "time", "source"}));
        for (size_t i = 0; i < f.points.size(); ++i) {
            const LidarPoint &a = f.points[i], &b = r.points[i];
            EXPECT_EQ(a.x, b.x);
            EXPECT_EQ(a.y, b.y);
            EXPECT_EQ(a.z, b.z);
            EXPECT_EQ(a.intensity, b.intensity);
            EXPECT_EQ(a.ring, b.ring);
            EXPECT_EQ(a.return_index, b.return_index);
            EXPECT_EQ(a.time_s, b.time_s);
            EXPECT_EQ(a.source, b.source);
            EXPECT_NEAR(b.range_m, a.range_m, 1e-5 * a.range_m);
        }
        EXPECT_EQ(r.start_s, 2.0) << name;
        ASSERT_TRUE(r.has_viewpoint) << name;
        EXPECT_NEAR((r.viewpoint.t - f.start_pose.t).norm(), 0, 1e-8);
        EXPECT_NEAR((r.viewpoint.R - f.start_pose.R).norm(), 0, 1e-8);  // 18° about z
    }
}

TEST(Lidar, DriversCloudsAreReadWithTheirOwnFieldsAndNoReturnsSkipped)
{
    // An Ouster-like organised cloud, ASCII: t in nanoseconds, fields smokescan does not take
    // (reflectivity, ambient), a COUNT 3 field, and NaN where the beam had no return.
    const std::string ouster =
        "# from a driver\nVERSION 0.7\nFIELDS x y z intensity t reflectivity ring normal\n"
        "SIZE 4 4 4 4 4 2 2 4\nTYPE F F F F U U U F\nCOUNT 1 1 1 1 1 1 1 3\n"
        "WIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n"
        "1.5 0 0.25 12 50000000 7 3 0 0 1\n"
        "nan nan nan 0 51000000 0 4 0 0 1\n"
        "0 -2 0 30 52000000 9 5 0 0 1\n";
    const PointCloudFile o = parsePointCloud(ouster, "os.pcd");
    ASSERT_EQ(o.points.size(), 2u);
    EXPECT_EQ(o.skipped, 1u);
    EXPECT_FLOAT_EQ(o.points[0].x, 1.5f);
    EXPECT_FLOAT_EQ(o.points[0].range_m, std::sqrt(1.5f * 1.5f + 0.25f * 0.25f));
    EXPECT_FLOAT_EQ(o.points[0].time_s, 0.05f);
    EXPECT_EQ(o.points[0].ring, 3);
    EXPECT_EQ(o.points[1].ring, 5);
    EXPECT_EQ(o.points[1].beam, 2u);  // its index in the file, the skipped point counted
    EXPECT_TRUE(std::isnan(o.start_s));
    // A PLY in ASCII with double coordinates and a face element after the vertices.
    const std::string ply =
        "ply\nformat ascii 1.0\ncomment by hand\nelement vertex 2\nproperty double x\n"
        "property double y\nproperty double z\nproperty ushort ring\nelement face 0\n"
        "property list uchar int vertex_indices\nend_header\n3 4 0 7\n-1 0 0 8\n";
    const PointCloudFile p = parsePointCloud(ply, "hand.ply");
    ASSERT_EQ(p.points.size(), 2u);
    EXPECT_FLOAT_EQ(p.points[0].range_m, 5.0f);
    EXPECT_EQ(p.points[1].ring, 8);
}

TEST(Lidar, BadPointCloudsAreOneLineErrorsNamingTheLine)
{
    const std::string h = kPcdHeader;
    expectRefused(h + "WIDTH 3\nHEIGHT 1\nPOINTS 3\nDATA binary\n" + std::string(30, '\0'),
                  "bad.pcd: holds 2 whole points of the 3 its header gives (truncated)");
    expectRefused(h + "WIDTH 1\nPOINTS 1\nDATA binary_compressed\n", "bad.pcd:8: DATA binary_compressed is not read");
    expectRefused("VERSION 0.7\nFIELDS x y\nSIZE 4 4\nTYPE F F\nPOINTS 0\nDATA ascii\n", "bad.pcd: has no field 'z'");
    expectRefused("FIELDS x y z\nSIZE 4 4 2\nTYPE F F F\nPOINTS 0\nDATA ascii\n", "field 'z' has type F of 2 bytes");
    expectRefused("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 2 1\nPOINTS 0\nDATA ascii\n",
                  "field 'y' has 2 values a point, not 1");
    expectRefused(h + "WIDTH 2\nHEIGHT 2\nPOINTS 3\nDATA ascii\n", "POINTS 3 is not WIDTH × HEIGHT");
    expectRefused(h + "POINTS 2\nDATA ascii\n1 2 3\n1 2\n", "bad.pcd:9: 2 values, not the 3 the header gives");
    expectRefused(h + "POINTS 2\nDATA ascii\n1 2 3\n", "bad.pcd:9: the file ends after 1 of 2 points");
    expectRefused(h + "POINTS 1\nDATA ascii\n1 2 x3\n", "bad.pcd:8: 'x3' is not a finite number");
    expectRefused(h + "POINTS 99999999\nDATA ascii\n", "POINTS '99999999' is not a whole number from 0 to 8000000");
    expectRefused(h + "POINTS 1\n", "the header ends without its data");
    expectRefused(h + "COLOUR 1\nDATA ascii\n", "bad.pcd:6: 'COLOUR' is not a PCD header line");
    expectRefused("\n \n", "the header ends without its data");  // found by the fuzzer: a line of blanks
    expectRefused("ply\nformat binary_big_endian 1.0\nelement vertex 0\nend_header\n",
                  "bad.pcd:2: 'format binary_big_endian 1.0': ascii or binary_little_endian 1.0 are read");
    expectRefused(
        "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nend_header\n" +
            std::string(12, '\0'),
        "holds 1 whole points of the 4 its header gives (truncated)");
    expectRefused("ply\nformat ascii 1.0\nelement vertex 1\nproperty half x\nend_header\n",
                  "property type 'half' is not a PLY scalar type");
    // A field twice: refused by name (the second would be read in place of the first).
    expectRefused("FIELDS x y z x\nSIZE 4 4 4 4\nTYPE F F F F\nPOINTS 0\nDATA ascii\n",
                  "bad.pcd: has the field 'x' twice");
    expectRefused(
        "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
        "property float y\nend_header\n",
        "has the field 'y' twice");
    // Two names of one value (a point's time in s and Ouster's t in ns): refused, not one read.
    expectRefused("FIELDS x y z time t\nSIZE 4 4 4 4 4\nTYPE F F F F U\nPOINTS 0\nDATA ascii\n",
                  "bad.pcd: has the fields 'time' and 't', which both name one value of a point");
    // A .ply whose magic is wrong is named a bad PLY, not a bad PCD.
    try {
        parsePointCloud("plx\nformat ascii 1.0\n", "frame.ply");
        ADD_FAILURE() << "a bad PLY was read";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("frame.ply:1: is not a PLY file (its first line is not 'ply')"),
                  std::string::npos)
            << e.what();
    }
    try {
        readPointCloud(scratch("lidar_readback_dir").string());
        ADD_FAILURE() << "a folder was read";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("is a folder, not a point-cloud file"), std::string::npos) << e.what();
    }
}

TEST(Lidar, AWallBehindFogFromTheSensorRisesOutOfTheNearFieldsEchoAndBrighterWallsAreNoLessSeen)
{
    // Fog of σ_t 0.2 /m (albedo 0.2) from behind the sensor to 5 cm before a wall at 5 m: its echo
    // is above the threshold from the first sample (the blind zone) all the way to the wall, so
    // the wall's pulse is a peak rising out of that run. Each beam returns the wall, and nothing
    // from the blind zone, with the calibrated reflectivity of the clear wall times the fog's
    // two-way transmittance T² = e^(−2·0.2·4.95 m/cos a), read over the valley before the peak:
    // there the fog's echo is stronger than under the peak (the fog ends before the wall), so the
    // height reads low by at most that echo, relatively 1/ρ more for a darker wall, and the box's
    // voxels reach up to half a voxel past 4.95 m (1 % more two-way τ): bound 2 % + 2 %/ρ (seen:
    // 8.6 % at ρ 0.2, 5.0 % at 0.5, 3.4 % at 0.9); no more than the receiver's noise high (0.4 %).
    const std::string preset = patternedLidar("fogroom", fan(200, 1.0));
    const double tau = 0.2 * 4.95;
    for (double rho : {0.2, 0.5, 0.9}) {
        const LidarFrame fog = frameOf(wallScene(5, rho, 0, 0.2, -0.5, 4.95, 6, 0.2), preset, ReturnMode::Dual);
        const LidarFrame clear = frameOf(wallScene(5, rho), preset, ReturnMode::Dual);
        ASSERT_EQ(fog.points.size(), 200u) << "rho " << rho;
        ASSERT_EQ(clear.points.size(), 200u);
        double worst_range = 0, lowest = 1, highest = 0;
        for (size_t i = 0; i < 200; ++i) {
            const LidarPoint &p = fog.points[i], &q = clear.points[i];
            EXPECT_EQ(p.source, uint8_t(EchoSource::Surface));
            const double c = std::cos(std::atan2(p.y, p.x)), t2 = std::exp(-2 * tau / c);
            const double read = p.intensity / q.intensity / t2;
            lowest = std::min(lowest, read), highest = std::max(highest, read);
            worst_range = std::max(worst_range, std::abs(p.x - 5.0));
            // The leading edge over a falling pedestal reads late: within 2 cm (seen 1.5 cm at ρ 0.2).
            EXPECT_NEAR(p.x, 5.0, 0.02);
            EXPECT_GE(read, 1 - 0.02 - 0.02 / rho);
            EXPECT_LE(read, 1.01);
        }
        std::printf("rho %.1f in fog: range within %.1f mm, intensity %.3f–%.3f of the clear one's times T²\n", rho,
                    1e3 * worst_range, lowest, highest);
    }
    // A brighter wall is never seen less often, nearer or farther and in denser fog (the receiver
    // used to lose a wall whose echo merged into the near field's: the brighter, the more often).
    const std::string fewer = patternedLidar("fogroom50", fan(50, 1.0));
    for (double density : {0.2, 0.5, 1.0})
        for (double d : {2.0, 3.0, 5.0}) {
            size_t before = 0;
            for (double rho : {0.05, 0.2, 0.5, 0.9}) {
                const LidarFrame f = frameOf(wallScene(d, rho, 0, density, -0.5, d - 0.05), fewer, ReturnMode::Last);
                const size_t wall = size_t(std::count_if(f.points.begin(), f.points.end(), [](const LidarPoint& p) {
                    return p.source == uint8_t(EchoSource::Surface);
                }));
                EXPECT_GE(wall + 2, before) << "density " << density << ", wall at " << d << " m, rho " << rho;
                before = wall;
            }
        }
}
