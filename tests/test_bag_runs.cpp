// The bags `render --bag` and `omnirange --bag` write, read back by the independent readers
// (tests/bag_readers.hpp) and compared value by value with the same run's images and logs.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "bag_readers.hpp"
#include "cli_run.hpp"
#include "omni_court.hpp"
#include "smokescan/bag/bag_input.hpp"
#include "smokescan/bag/mcap_writer.hpp"
#include "smokescan/bag/scan_messages.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/io/image.hpp"
#include "smokescan/io/recorded.hpp"
#include "smokescan/lidar/lidar_spec.hpp"
#include "smokescan/omni/omni_scan_message.hpp"
#include "smokescan/pipeline/lidar_frames.hpp"
#include "smokescan/pipeline/run_control.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/sensor_config/lms200.hpp"

using namespace smokescan;
using namespace smokescan::test;

namespace {

Eigen::Quaterniond rotationOf(const nlohmann::json& transform)
{
    const auto& q = transform["rotation"];
    return Eigen::Quaterniond(q["w"].get<double>(), q["x"].get<double>(), q["y"].get<double>(), q["z"].get<double>());
}

Eigen::Vector3d translationOf(const nlohmann::json& transform)
{
    const auto& t = transform["translation"];
    return {t["x"].get<double>(), t["y"].get<double>(), t["z"].get<double>()};
}

}  // namespace

TEST(BagCli, RenderedFramesGoOnCameraImageInTheCamerasOpticalFrame)
{
    SMOKESCAN_NEED_READERS();
    const fs::path bag = dir() / "render_bag";
    fs::remove_all(bag);
    const std::string png = (dir() / "render_{i}.png").string();
    const CliRun r = cli("render bocas --from 100 --to 100.5 --every 0.5 --width 64 --height 48 --spp 2 --out " + png +
                         " --bag " + bag.string());
    ASSERT_EQ(r.status, 0) << r.err;
    const nlohmann::json j = readIndependently((bag / "render_bag_0.mcap").string());
    EXPECT_TRUE(j["problems"].empty()) << j["problems"];
    const Camera cam = loadScene("bocas").cameras.front();
    size_t k = 0, statics = 0;
    for (const auto& m : j["messages"]) {
        const auto& msg = m["message"];
        if (m["topic"] == "/tf_static") {
            ++statics;
            ASSERT_EQ(msg["transforms"].size(), 2u);
            const auto& mount = msg["transforms"][0];
            EXPECT_EQ(mount["header"]["frame_id"], "map");
            EXPECT_EQ(mount["child_frame_id"], cam.name);
            EXPECT_LT((translationOf(mount["transform"]) - cam.pose.t).norm(), 1e-12);
            EXPECT_LT((rotationOf(mount["transform"]).toRotationMatrix() - cam.pose.R).norm(), 1e-12);
            // REP 103's optical frame: +z along the view (the camera's +x), +x right (its −y),
            // +y down (its −z).
            const auto& optical = msg["transforms"][1];
            EXPECT_EQ(optical["header"]["frame_id"], cam.name);
            EXPECT_EQ(optical["child_frame_id"], cam.name + "_optical_frame");
            EXPECT_EQ(translationOf(optical["transform"]), Eigen::Vector3d::Zero());
            const Eigen::Quaterniond q = rotationOf(optical["transform"]);
            EXPECT_LT((q * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitX()).norm(), 1e-12);
            EXPECT_LT((q * Eigen::Vector3d::UnitX() + Eigen::Vector3d::UnitY()).norm(), 1e-12);
            EXPECT_LT((q * Eigen::Vector3d::UnitY() + Eigen::Vector3d::UnitZ()).norm(), 1e-12);
            continue;
        }
        ASSERT_EQ(m["topic"], "/camera/image");
        EXPECT_EQ(std::stoull(m["logTime"].get<std::string>()), 100000000000ull + 500000000ull * k);
        EXPECT_EQ(msg["header"]["frame_id"], cam.name + "_optical_frame");
        EXPECT_EQ(msg["header"]["stamp"]["sec"], 100);
        EXPECT_EQ(msg["header"]["stamp"]["nanosec"], 500000000 * k);
        EXPECT_EQ(msg["encoding"], "rgb8");
        EXPECT_EQ(msg["step"], 64 * 3);
        EXPECT_EQ(msg["is_bigendian"], 0);
        ASSERT_EQ(msg["width"], 64);
        ASSERT_EQ(msg["height"], 48);
        const Image frame = readImage((dir() / ("render_000" + std::to_string(k) + ".png")).string());
        const std::string data = base64(msg["data"].get<std::string>());
        ASSERT_EQ(data.size(), size_t(64 * 48 * 3));
        for (size_t p = 0; p < size_t(64 * 48); ++p)
            for (size_t c = 0; c < 3; ++c)
                ASSERT_EQ(int(uint8_t(data[3 * p + c])),
                          int(std::lround(frame.data[p * size_t(frame.channels) + c] * 255)))
                    << k << " pixel " << p;
        ++k;
    }
    EXPECT_EQ(k, 2u);
    EXPECT_EQ(statics, 1u);
    EXPECT_FALSE(j["topics"].contains("/tf")) << "a fixed camera: no robot, no /tf";
    // /tf_static offered transient-local and reliable (durability 1, reliability 1), as tf2's
    // static broadcaster offers it, so that a played bag reaches late subscribers.
    const std::string meta = slurp(bag / "metadata.yaml");
    const size_t tf_static = meta.find("name: /tf_static");
    ASSERT_NE(tf_static, std::string::npos) << meta;
    const std::string qos = meta.substr(tf_static, meta.find("message_count", tf_static) - tf_static);
    EXPECT_NE(qos.find("reliability: 1\\n  durability: 1"), std::string::npos) << qos;
    // A bad time fails before any frame is rendered, naming the option.
    expectBad("render bocas --time -5 --width 8 --height 6 --bag " + (dir() / "render_bad").string(), "--time",
              (dir() / "render_bad").string());
    expectBad("render bocas --from 1 --to 2 --width 8 --height 6 --bag " + (dir() / "render_bad").string(), "--every",
              (dir() / "render_bad").string());
}

TEST(BagCli, TheOmnicamsRangesGoOnOmniScanAndItsLasersOnScanAsTheirLogs)
{
    SMOKESCAN_NEED_READERS();
    const std::string scene = file("court.toml", omniCourt());
    const std::string out = file("omni.log"), laser = file("laser.log");
    const fs::path bag = dir() / "omni_bag";
    fs::remove_all(bag);
    // Walls nearer than 1.4 m (right: 1.2 m) read as too near, beyond 2.2 m (behind: 2.5 m) as none.
    const CliRun r =
        cli("omnirange " + scene + " --train 0 --from 0 --to 1 --spp 4 --min-range 1.4 --max-range 2.2 --out " + out +
            " --laser-out " + laser + " --bag " + bag.string());
    ASSERT_EQ(r.status, 0) << r.err;
    const RecordedLog omni = readRecordedLog(out), lms = readRecordedLog(laser);
    ASSERT_EQ(omni.scans.size(), 2u);
    const nlohmann::json j = readIndependently((bag / "omni_bag_0.mcap").string());
    EXPECT_TRUE(j["problems"].empty()) << j["problems"];
    size_t k_omni = 0, k_laser = 0, tf = 0;
    std::map<std::string, nlohmann::json> mounts;
    for (const auto& m : j["messages"]) {
        const auto& msg = m["message"];
        const double t = double(std::stoull(m["logTime"].get<std::string>())) * 1e-9;
        if (m["topic"] == "/tf") {
            ++tf;
            EXPECT_EQ(msg["transforms"][0]["child_frame_id"], "r");
        } else if (m["topic"] == "/tf_static") {
            for (const auto& x : msg["transforms"]) mounts[x["child_frame_id"].get<std::string>()] = x;
        } else if (m["topic"] == "/omni/scan") {
            ASSERT_LT(k_omni, omni.scans.size());
            const LaserLogScan& s = omni.scans[k_omni++];
            EXPECT_NEAR(t, s.time_s, 1e-9);
            EXPECT_NEAR(
                msg["header"]["stamp"]["sec"].get<double>() + msg["header"]["stamp"]["nanosec"].get<double>() * 1e-9,
                s.time_s, 1e-9);
            EXPECT_EQ(msg["header"]["frame_id"], "omni");
            EXPECT_EQ(msg["angle_min"].get<double>(), 0.0);
            EXPECT_FLOAT_EQ(msg["angle_increment"].get<float>(), float(2 * M_PI / 360));
            EXPECT_FLOAT_EQ(msg["range_max"].get<float>(), 2.2f);
            EXPECT_FLOAT_EQ(msg["range_min"].get<float>(), 1.4f);
            const auto& ranges = msg["ranges"];
            ASSERT_EQ(ranges.size(), s.range.size());
            size_t none = 0, near = 0, logged_none = 0, logged_near = 0;
            for (size_t b = 0; b < s.range.size(); ++b) {
                // The log's scanline b is at azimuth 2π·b/360 (wrapped to ±π), as the bag's.
                EXPECT_NEAR(std::remainder(s.angle_rad[b] - 2 * M_PI * double(b) / 360, 2 * M_PI), 0, 1e-6);
                // No obstacle within range is +Inf, one too near −Inf: the log writes the limits.
                const double got = number(ranges[b]);
                none += std::isinf(got) && got > 0;
                near += std::isinf(got) && got < 0;
                logged_none += s.range[b] == 2200;
                logged_near += s.range[b] == 1400;
                if (std::isinf(got))
                    EXPECT_EQ(s.range[b], got > 0 ? 2200 : 1400) << b;
                else
                    EXPECT_NEAR(got * 1000, s.range[b], 0.5 + 1e-3) << b;
            }
            EXPECT_EQ(none, logged_none);
            EXPECT_EQ(near, logged_near);
            EXPECT_GT(none, 60u) << "behind the robot, a quarter of the scanlines";
            EXPECT_GT(near, 30u) << "to its right";
        } else if (m["topic"] == "/scan") {
            ASSERT_LT(k_laser, lms.scans.size());
            const LaserLogScan& s = lms.scans[k_laser++];
            EXPECT_NEAR(t, s.time_s, 1e-9);
            EXPECT_EQ(msg["header"]["frame_id"], "sick");
            ASSERT_EQ(msg["ranges"].size(), s.range.size());
            for (size_t b = 0; b < s.range.size(); ++b)
                if (s.range[b] < lms_code::kNoEcho)  // below the LMS200's error values
                    EXPECT_FLOAT_EQ(number(msg["ranges"][b]), float(s.range[b] * 0.001)) << b;
        }
    }
    EXPECT_EQ(k_omni, 2u);
    EXPECT_EQ(k_laser, 2u);
    EXPECT_EQ(tf, 2u) << "the robot's pose once a frame, for both sensors";
    // Each sensor's mount on the robot, once (omni_court.hpp).
    ASSERT_EQ(mounts.size(), 2u);
    for (const char* name : {"omni", "sick"}) {
        ASSERT_TRUE(mounts.count(name)) << name;
        EXPECT_EQ(mounts[name]["header"]["frame_id"], "r");
    }
    EXPECT_NEAR(translationOf(mounts["omni"]["transform"]).z(), 0.931, 1e-12);
    EXPECT_NEAR(translationOf(mounts["sick"]["transform"]).z(), 0.3, 1e-12);
    // the LMS200 turned −90°: its +x is the robot's −y
    EXPECT_LT((rotationOf(mounts["sick"]["transform"]) * Eigen::Vector3d::UnitX() + Eigen::Vector3d::UnitY()).norm(),
              1e-12);
}

TEST(BagCli, TheSaturationOfABagsFramesIsMeasuredAsTheIndependentWriterDrewThem)
{
    SMOKESCAN_NEED_READERS();
    const std::string mcap = (dir() / "frames_written.mcap").string(), csv = file("bag_sat.csv");
    fs::remove(mcap);
    const std::string cmd = "node " + readersDir() + "/write_bag.mjs " + mcap + " 2 682 4";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    // The block drawn in each frame (bgra8, padded rows): saturation 0.2 k at 10 + 0.5 k s.
    const CliRun r = cli("saturation --bag " + mcap + " --rect block=2,1,4,3 --out " + csv);
    ASSERT_EQ(r.status, 0) << r.err;
    const SaturationSeries s = readSaturationCsv(csv);
    ASSERT_EQ(s.time_s.size(), 4u);
    ASSERT_EQ(s.patch_names, std::vector<std::string>{"block"});
    for (size_t k = 0; k < 4; ++k) {
        EXPECT_DOUBLE_EQ(s.time_s[k], 10 + 0.5 * double(k));
        EXPECT_NEAR(s.saturation[k], 0.2 * double(k), 1e-6) << k;
        EXPECT_NEAR(s.patch[0][k], 0.2 * double(k), 1e-6) << k;
    }
    // A region over the grey border too: its pixels dilute the mean by their share (12 of 24).
    ASSERT_EQ(cli("saturation --bag " + mcap + " --rect wide=2,0,4,6 --out " + csv).status, 0);
    EXPECT_NEAR(readSaturationCsv(csv).saturation[3], 0.6 * 12 / 24, 1e-6);
    // The topic is the bag's only Image topic; a LaserScan topic is refused by name.
    const std::string bad = file("bag_sat_bad.csv");
    expectBad("saturation --bag " + mcap + " --topic /front/scan --rect b=0,0,2,2 --out " + bad,
              "topic /front/scan is sensor_msgs/msg/LaserScan, not sensor_msgs/msg/Image", bad);
    expectBad("saturation --bag " + mcap + " --out " + bad, "give the target's region", bad);
    expectBad("saturation --bag " + mcap + " --rect b=0,0,2,2 --fps 10 --out " + bad, "--fps", bad);
    expectBad("saturation --topic /cam/image --rect b=0,0,2,2 --out " + bad, "--topic", bad);
    expectBad("saturation --bag " + mcap + " --topic '' --rect b=0,0,2,2 --out " + bad, "--topic", bad);
    // A frame file that is a FIFO is refused, not waited on.
    const std::string fifo = (dir() / "frame_fifo.png").string();
    fs::remove(fifo);
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    expectBad("saturation " + fifo + " --rect b=0,0,2,2 --out " + bad, "is not a regular file", bad);
    fs::remove(fifo);
}

TEST(BagCli, AFitOnABagsCameraFramesIsTheFitOnTheSameFramesAsFiles)
{
    SMOKESCAN_NEED_READERS();
    // bocas at 2 Hz through the smoke's onset, the camera's frames (0.5 Hz, its clock 0.25 s ahead)
    // rendered into the bag and kept as PNGs.
    const fs::path bag = dir() / "fit_frames", frames = dir() / "fit_frames_png";
    fs::remove_all(bag);
    fs::remove_all(frames);
    const CliRun s = cli("scan bocas --from 90 --to 110 --rate 2 --quiet --bag " + bag.string() + " --saturation-out " +
                         file("fit_frames.csv") +
                         " --saturation-render --saturation-width 48 --saturation-height 36 --saturation-spp 1 "
                         "--saturation-rate 0.5 --camera-offset 0.25 --saturation-frames " +
                         frames.string());
    ASSERT_EQ(s.status, 0) << s.err;
    // The frames on /camera/image as the camera delivered them: each the same bytes as its PNG, on
    // the camera's own clock.
    const nlohmann::json j = readIndependently((bag / "fit_frames_0.mcap").string());
    EXPECT_TRUE(j["problems"].empty()) << j["problems"];
    size_t k = 0;
    for (const auto& m : j["messages"]) {
        if (m["topic"] != "/camera/image") continue;
        EXPECT_EQ(m["schema"], "sensor_msgs/msg/Image");
        const auto& msg = m["message"];
        EXPECT_EQ(std::stoull(m["logTime"].get<std::string>()), 90250000000ull + 2000000000ull * k);
        EXPECT_EQ(msg["encoding"], "rgb8");
        ASSERT_EQ(msg["width"], 48);
        ASSERT_EQ(msg["height"], 36);
        EXPECT_EQ(msg["step"], 48 * 3);
        const Image png = readImage((frames / fmt("frame_%06zu.png", k)).string());
        const std::string data = base64(msg["data"].get<std::string>());
        ASSERT_EQ(data.size(), size_t(48 * 36 * 3));
        for (size_t p = 0; p < size_t(48 * 36); ++p)
            for (size_t c = 0; c < 3; ++c)
                ASSERT_EQ(int(uint8_t(data[3 * p + c])), int(std::lround(png.data[p * size_t(png.channels) + c] * 255)))
                    << k << " pixel " << p;
        ++k;
    }
    EXPECT_EQ(k, 11u);
    // The target's box in the frames, from the id images (object = the surface's index).
    const Scene scene = loadScene("bocas");
    const Image ids = readImage((frames / "ids" / "frame_000000.exr").string());
    const int object = ids.channel("object", 0);
    int x0 = ids.width, y0 = ids.height, x1 = -1, y1 = -1;
    for (int y = 0; y < ids.height; ++y)
        for (int x = 0; x < ids.width; ++x) {
            const int id = int(std::lround(
                ids.data[(size_t(y) * size_t(ids.width) + size_t(x)) * size_t(ids.channels) + size_t(object)]));
            if (id < 0 || id >= int(scene.surfaces.size()) || scene.surfaces[size_t(id)].name.rfind("target_", 0) != 0)
                continue;
            x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
        }
    ASSERT_GE(x1, x0 + 2) << "the target is not in the frame";
    const std::string rect = " --rect target=" + std::to_string(x0 + 1) + "," + std::to_string(y0 + 1) + "," +
        std::to_string(x1 - x0 - 1) + "," + std::to_string(y1 - y0 - 1);
    // The same frames as PNG files with their camera times, measured by the folder's path (OpenImageIO
    // reading the PNGs): the same series, to the CSV's last digit.
    const std::string from_pngs = file("fit_frames_png.csv"), from_bag = file("fit_frames_bag.csv");
    ASSERT_EQ(cli("saturation " + frames.string() + rect + " --timestamps " + (frames / "timestamps.csv").string() +
                  " --out " + from_pngs)
                  .status,
              0);
    ASSERT_EQ(cli("saturation --bag " + bag.string() + rect + " --out " + from_bag).status, 0);
    EXPECT_EQ(slurp(from_bag), slurp(from_pngs));
    EXPECT_EQ(readSaturationCsv(from_bag).time_s.size(), 11u);
    // fit measures the bag's frames itself: the fit on the CSV (whose 10 digits round the series).
    const std::string common = " --bag " + bag.string() + " --scene bocas";
    const CliRun a = cli("fit" + common + " --saturation " + from_pngs + " --out " + file("fit_png.toml"));
    ASSERT_EQ(a.status, 0) << a.err;
    const CliRun b = cli("fit" + common + " --saturation " + bag.string() + rect + " --out " + file("fit_bag.toml"));
    ASSERT_EQ(b.status, 0) << b.err;
    const auto ja = nlohmann::json::parse(slurp(file("fit_png_report.json")));
    const auto jb = nlohmann::json::parse(slurp(file("fit_bag_report.json")));
    ASSERT_EQ(ja["groups"].size(), jb["groups"].size());
    size_t fitted = 0;
    for (size_t g = 0; g < ja["groups"].size(); ++g) {
        const auto& ta = ja["groups"][g]["threshold"];
        const auto& tb = jb["groups"][g]["threshold"];
        ASSERT_EQ(ta["fitted"], tb["fitted"]) << g;
        if (!ta["fitted"].get<bool>()) continue;
        ++fitted;
        EXPECT_NEAR(ta["S_star"]["value"].get<double>(), tb["S_star"]["value"].get<double>(), 1e-7) << g;
        EXPECT_NEAR(ta["S_star"]["std_error"].get<double>(), tb["S_star"]["std_error"].get<double>(), 1e-7) << g;
    }
    EXPECT_EQ(fitted, 3u) << "each target's threshold";
    EXPECT_NE(jb["sources"].dump().find("/camera/image"), std::string::npos) << jb["sources"];
    // The bag's options without a bag, and a bag without a region.
    expectBad("fit" + common + " --saturation " + from_pngs + rect + " --out " + file("fit_x.toml"), "is not a bag",
              file("fit_x.toml"));
    expectBad("fit" + common + " --saturation " + bag.string() + " --out " + file("fit_x.toml"),
              "give the target's region", file("fit_x.toml"));
}

TEST(Bag, ImagesAreDecodedByTheirEncodingAndRowStep)
{
    // 3×2 pixels, rows padded to 16 bytes; pixel (x, y) is (R, G, B) = (10 + x, 20 + y, 30 + x + y).
    for (const std::string enc : {"rgb8", "bgr8", "rgba8", "bgra8"}) {
        const bool bgr = enc[0] == 'b';
        const size_t bytes = enc.size() == 5 ? 4 : 3;
        ImageMsg m;
        m.width = 3, m.height = 2, m.step = 16, m.encoding = enc;
        m.data.assign(32, 99);
        for (uint8_t y = 0; y < 2; ++y)
            for (uint8_t x = 0; x < 3; ++x) {
                uint8_t* p = m.data.data() + y * 16 + x * bytes;
                p[bgr ? 2 : 0] = uint8_t(10 + x), p[1] = uint8_t(20 + y), p[bgr ? 0 : 2] = uint8_t(30 + x + y);
                if (bytes == 4) p[3] = 255;
            }
        Image img = imageOf(m, "frame");
        ASSERT_EQ(img.channels, 3);
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 3; ++x) {
                EXPECT_FLOAT_EQ(img.at(x, y, 0), float(10 + x) / 255) << enc;
                EXPECT_FLOAT_EQ(img.at(x, y, 1), float(20 + y) / 255) << enc;
                EXPECT_FLOAT_EQ(img.at(x, y, 2), float(30 + x + y) / 255) << enc;
            }
    }
    auto error = [](ImageMsg m) {
        try {
            (void)imageOf(m, "f.mcap: message 3 on /cam");
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    ImageMsg ok;
    ok.width = 2, ok.height = 1, ok.step = 6, ok.encoding = "rgb8", ok.data.assign(6, 0);
    ImageMsg mono = ok;
    mono.encoding = "mono8";
    EXPECT_NE(error(mono).find("f.mcap: message 3 on /cam: is encoded 'mono8'"), std::string::npos) << error(mono);
    ImageMsg short_step = ok;
    short_step.step = 5, short_step.data.assign(5, 0);
    EXPECT_NE(error(short_step).find("row step of 5 bytes"), std::string::npos) << error(short_step);
    ImageMsg empty = ok;
    empty.width = 0, empty.step = 0, empty.data.clear();
    EXPECT_NE(error(empty).find("0×1 pixels"), std::string::npos) << error(empty);
}

TEST(Bag, ABagIsKnownByItsFolderOrMagicAndItsFramesStampsMustIncrease)
{
    const fs::path mcap = dir() / "frames_unit.mcap";
    {
        std::ostringstream o;
        McapWriter w(o, McapWriterConfig{});
        const uint16_t ch = w.addChannel(w.addSchema(kImageType.name, "ros2msg", kImageType.definition), "/cam", "cdr");
        for (double t : {1.0, 2.0, 1.5}) {
            ImageMsg m;
            m.header.stamp = RosTime::fromSeconds(t);
            m.width = 1, m.height = 1, m.step = 3, m.encoding = "rgb8", m.data = {200, 100, 50};
            w.write(ch, m.header.stamp.nanoseconds(), m.header.stamp.nanoseconds(), encode(m));
        }
        w.finish();
        std::ofstream(mcap, std::ios::binary) << o.str();
    }
    // Two Image topics and no topic named: that is the error, before any frame's own.
    const fs::path two = dir() / "frames_two.mcap";
    {
        std::ostringstream o;
        McapWriter w(o, McapWriterConfig{});
        const uint16_t schema = w.addSchema(kImageType.name, "ros2msg", kImageType.definition);
        const uint16_t a = w.addChannel(schema, "/a", "cdr"), b = w.addChannel(schema, "/b", "cdr");
        ImageMsg m;
        m.width = 1, m.height = 1, m.step = 3, m.encoding = "mono8", m.data = {0, 0, 0};
        w.write(a, 1, 1, encode(m));
        w.write(b, 2, 2, encode(m));
        w.finish();
        std::ofstream(two, std::ios::binary) << o.str();
    }
    try {
        (void)readBagImages(two.string(), "", [](ImageMsg&& m, const std::string& what) { (void)imageOf(m, what); });
        FAIL() << "two Image topics read without one named";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("has several Image topics (/a /b): give its topic"), std::string::npos)
            << e.what();
    }
    EXPECT_TRUE(isBagPath(mcap.string()));
    EXPECT_TRUE(isBagPath(dir().string()));
    EXPECT_FALSE(isBagPath(file("not_a_bag.csv", "time_s,saturation\n1,0.2\n")));
    EXPECT_FALSE(isBagPath(file("short.mcap", "\x89MC")));
    EXPECT_FALSE(isBagPath((dir() / "missing.mcap").string()));
    std::vector<double> stamps;
    try {
        (void)readBagImages(mcap.string(), "", [&](ImageMsg&& m, const std::string&) {
            stamps.push_back(double(m.header.stamp.nanoseconds()) * 1e-9);
        });
        FAIL() << "a stamp going back was read";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("message 2 on /cam: has a stamp that does not follow"), std::string::npos)
            << e.what();
    }
    EXPECT_EQ(stamps, (std::vector<double>{1.0, 2.0}));
}

TEST(Bag, TheOmnicamsScanlinesAreALaserScanFromItsPlusXWithRep117Limits)
{
    OmniRangeResult r;
    r.range_m = {1.25, 0.3, 3.8, 2.0};
    r.status = {OmniRangeStatus::Hit, OmniRangeStatus::MinRange, OmniRangeStatus::MaxRange, OmniRangeStatus::Hit};
    r.angle_rad = {0, M_PI / 2, M_PI, -M_PI / 2};
    OmniRangeConfig cfg;
    const LaserScanMsg m = omniLaserScanOf(r, cfg, 12.5, 0.2, "omni");
    EXPECT_EQ(m.header.stamp.sec, 12);
    EXPECT_EQ(m.header.stamp.nanosec, 500000000u);
    EXPECT_EQ(m.header.frame_id, "omni");
    EXPECT_EQ(m.angle_min, 0.0f);
    EXPECT_FLOAT_EQ(m.angle_increment, float(M_PI / 2));
    EXPECT_FLOAT_EQ(m.angle_max, float(3 * M_PI / 2));
    EXPECT_FLOAT_EQ(m.range_min, 0.3f);
    EXPECT_FLOAT_EQ(m.range_max, 3.8f);
    EXPECT_FLOAT_EQ(m.scan_time, 0.2f);
    EXPECT_EQ(m.time_increment, 0.0f);
    ASSERT_EQ(m.ranges.size(), 4u);
    EXPECT_EQ(m.ranges[0], 1.25f);
    EXPECT_TRUE(std::isinf(m.ranges[1]) && m.ranges[1] < 0);
    EXPECT_TRUE(std::isinf(m.ranges[2]) && m.ranges[2] > 0);
    EXPECT_EQ(m.ranges[3], 2.0f);
}

TEST(BagCli, APlanarMultiEchoLidarsFramesAlsoGoOnEchoesBeamByBeam)
{
    SMOKESCAN_NEED_READERS();
    // A 2D multi-echo scanner as a pattern file: 271 beams from −135° to +135° in 1° steps in its
    // x–y plane, a turn in 25 ms (40 Hz), dual returns (strongest and last).
    const fs::path d = dir() / "planar_lidar", bag = dir() / "planar_bag";
    fs::remove_all(bag);
    fs::create_directories(d);
    {
        std::ofstream beams(d / "pattern.csv");
        for (int i = 0; i < 271; ++i) beams << (-135 + i) << ", 0, " << fmt("%.9f", 0.025 * i / 360) << "\n";
        std::ofstream(d / "scanner.toml") << "name = \"scanner\"\npattern = \"file\"\npattern_file = \"pattern.csv\"\n"
                                             "wavelength_nm = 905\nrate_hz = 40\nrange_min_m = 0.1\nrange_max_m = 30\n"
                                             "return_modes = [\"strongest\", \"last\", \"dual\"]\nmax_echoes = 3\n";
    }
    const CliRun r = cli("scan plume --sensor " + (d / "scanner.toml").string() +
                         " --from 40 --to 40.05 --returns dual --bag " + bag.string());
    ASSERT_EQ(r.status, 0) << r.err;
    const nlohmann::json j = readIndependently((bag / "planar_bag_0.mcap").string());
    EXPECT_TRUE(j["problems"].empty()) << j["problems"];
    std::vector<nlohmann::json> clouds, echoes;
    for (const auto& m : j["messages"]) {
        if (m["topic"] == "/points") clouds.push_back(m);
        if (m["topic"] == "/echoes") echoes.push_back(m);
    }
    ASSERT_EQ(clouds.size(), 3u);  // 40, 40.025, 40.05 s
    ASSERT_EQ(echoes.size(), 3u);
    size_t doubles = 0;
    for (size_t k = 0; k < 3; ++k) {
        const auto& e = echoes[k]["message"];
        EXPECT_EQ(echoes[k]["schema"], "sensor_msgs/msg/MultiEchoLaserScan");
        EXPECT_EQ(echoes[k]["logTime"], clouds[k]["logTime"]);
        EXPECT_EQ(e["header"]["frame_id"], clouds[k]["message"]["header"]["frame_id"]);
        EXPECT_FLOAT_EQ(e["angle_min"].get<float>(), float(-135 * M_PI / 180));
        EXPECT_FLOAT_EQ(e["angle_increment"].get<float>(), float(M_PI / 180));
        EXPECT_NEAR(e["angle_max"].get<double>(), 135 * M_PI / 180, 1e-6);
        EXPECT_NEAR(e["time_increment"].get<double>(), 0.025 / 360, 1e-9);
        EXPECT_FLOAT_EQ(e["scan_time"].get<float>(), 0.025f);
        EXPECT_FLOAT_EQ(e["range_max"].get<float>(), 30.0f);
        ASSERT_EQ(e["ranges"].size(), 271u);
        ASSERT_EQ(e["intensities"].size(), 271u);
        // The cloud's points, each put on its beam by its azimuth, in order: the beam's echoes.
        std::vector<std::vector<float>> want(271), want_intensity(271);
        const auto& c = clouds[k]["message"];
        const std::string data = base64(c["data"].get<std::string>());
        for (size_t at = 0; at + 24 <= data.size(); at += 24) {
            float p[4];
            std::memcpy(p, data.data() + at, 16);
            const long b = std::lround(std::atan2(p[1], p[0]) * 180 / M_PI) + 135;
            ASSERT_TRUE(b >= 0 && b < 271) << b;
            want[size_t(b)].push_back(std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]));
            want_intensity[size_t(b)].push_back(p[3]);
        }
        for (size_t b = 0; b < 271; ++b) {
            const auto& got = e["ranges"][b]["echoes"];
            ASSERT_EQ(got.size(), want[b].size()) << "frame " << k << " beam " << b;
            doubles += got.size() == 2;
            for (size_t i = 0; i < got.size(); ++i) {
                EXPECT_NEAR(got[i].get<double>(), want[b][i], 1e-4 * want[b][i]) << k << " " << b << " " << i;
                EXPECT_EQ(e["intensities"][b]["echoes"][i].get<float>(), want_intensity[b][i]) << k << " " << b;
            }
        }
    }
    EXPECT_GE(doubles, 3u) << "the plume at 40 s: beams with a smoke echo and a wall's (6 in this seed)";
}

TEST(Bag, APatternIsAPlanarFanOnlyInOnePlaneWithEvenSteps)
{
    auto fanOf = [](int n, double step_deg, double elevation_deg = 0, int channel = 0) {
        std::vector<PatternBeam> p(static_cast<size_t>(n));
        for (int i = 0; i < n; ++i)
            p[size_t(i)] = {(10 + i * step_deg) * M_PI / 180, elevation_deg * M_PI / 180, channel, 1e-4 * i};
        return p;
    };
    const auto up = planarFan(fanOf(5, 2));
    ASSERT_TRUE(up.has_value());
    EXPECT_NEAR(up->angle_min_rad, 10 * M_PI / 180, 1e-15);
    EXPECT_NEAR(up->step_rad, 2 * M_PI / 180, 1e-15);
    EXPECT_NEAR(up->time_step_s, 1e-4, 1e-15);
    const auto down = planarFan(fanOf(5, -0.25));  // a clockwise sweep
    ASSERT_TRUE(down.has_value());
    EXPECT_NEAR(down->step_rad, -0.25 * M_PI / 180, 1e-15);
    EXPECT_FALSE(planarFan(fanOf(5, 2, 1.0)).has_value()) << "out of the plane";
    EXPECT_FALSE(planarFan(fanOf(5, 2, 0, 3)).has_value()) << "another channel";
    auto uneven = fanOf(5, 2);
    uneven[2].azimuth_rad += 0.1 * M_PI / 180;  // a twentieth of the step
    EXPECT_FALSE(planarFan(uneven).has_value()) << "an uneven step";
    EXPECT_FALSE(planarFan(fanOf(1, 2)).has_value()) << "one beam";
    // A UTM-30LX-EW's 1081 steps of 0.25° in a 25 ms turn, times rounded to µs and azimuths to
    // 1e-3°, as a pattern file may hold them: planar.
    std::vector<PatternBeam> utm(1081);
    for (size_t i = 0; i < utm.size(); ++i)
        utm[i] = {std::round((-135 + 0.25 * double(i)) * 1e3) / 1e3 * M_PI / 180, 0, 0,
                  std::round(0.025 * double(i) / 1440 * 1e6) / 1e6};
    ASSERT_TRUE(planarFan(utm).has_value());
    EXPECT_NEAR(planarFan(utm)->time_step_s, 0.025 / 1440, 1e-9);
    // Azimuths that wrap at ±180° (10° … 209° as −151°) are no even fan.
    auto wrapped = fanOf(200, 1.0);
    ASSERT_TRUE(planarFan(wrapped).has_value());
    for (PatternBeam& b : wrapped) b.azimuth_rad = std::remainder(b.azimuth_rad, 2 * M_PI);
    EXPECT_FALSE(planarFan(wrapped).has_value()) << "wrapped";
    LidarSpec vlp = lidarSpec("vlp16");
    EXPECT_FALSE(planarFan(framePattern(vlp)).has_value()) << "16 channels";
}

TEST(BagCli, ReadsThePointCloudsAnIndependentWriterWroteInOustersLayout)
{
    SMOKESCAN_NEED_READERS();
    const std::string mcap = (dir() / "independent_clouds.mcap").string();
    const std::string cmd = "node " + readersDir() + "/write_bag.mjs " + mcap + " 1 682 0 4";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    // The writer's rule (tests/js/write_bag.mjs): 48-byte points, rows padded to 160 bytes, Ouster's
    // `t` in ns, point (1, 2) without a return.
    std::vector<double> starts;
    const std::string topic =
        readBagPointClouds(mcap, "", [&](const PointCloud2Msg& m, double start_s, const std::string& what) {
            const PointCloudFile pc = pointCloudFileOf(m, what);
            const size_t k = starts.size();
            starts.push_back(start_s);
            EXPECT_NE(what.find("/ouster/points"), std::string::npos) << what;
            EXPECT_EQ(pc.fields,
                      (std::vector<std::string>{"x", "y", "z", "intensity", "t", "reflectivity", "ring", "ambient",
                                                "range"}));
            EXPECT_EQ(pc.skipped, 1u);
            ASSERT_EQ(pc.points.size(), 5u);
            for (size_t i = 0; i < pc.points.size(); ++i) {
                const LidarPoint& p = pc.points[i];
                const int r = int(i / 3), c = int(i % 3);
                EXPECT_EQ(p.x, float(double(k) + 0.25 * c)) << k << " " << i;
                EXPECT_EQ(p.y, float(r));
                EXPECT_EQ(p.z, -0.5f);
                EXPECT_EQ(p.intensity, float(10 * k + size_t(c)));
                EXPECT_EQ(p.ring, uint16_t(r));
                EXPECT_EQ(p.time_s, float(1000e-9 * (c + 1)));
                EXPECT_EQ(p.return_index, 0);
                EXPECT_FLOAT_EQ(p.range_m, std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z));
            }
        });
    EXPECT_EQ(topic, "/ouster/points");  // the only PointCloud2 topic, beside /front/scan and /tf
    ASSERT_EQ(starts.size(), 4u);
    for (size_t k = 0; k < starts.size(); ++k) EXPECT_DOUBLE_EQ(starts[k], 10 + 0.1 * double(k));
    try {
        (void)readBagPointClouds(mcap, "/front/scan", [](const PointCloud2Msg&, double, const std::string&) {});
        ADD_FAILURE() << "a LaserScan topic read as point clouds";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("/front/scan is sensor_msgs/msg/LaserScan"), std::string::npos)
            << e.what();
    }
}

TEST(BagCli, AROS1BagOfALidarsFramesGivesTheFramesFoldersDiagnosisAndFit)
{
    // A VLP-16 whose ring 5 reads 0.2 m long, scanned into a frames folder; Debian's python3-rosbag
    // writes its PCDs (read by the script's own parser) as PointCloud2s of two rows padded by 8
    // bytes each, recorded 1 ms after their stamps, in each compression (the point data hardly
    // compresses: lz4's decoding of compressed blocks is BagCli.ReadsTheRos1BagsDebiansRosbagWrote's).
    // Diagnosed and fitted from the ROS 1 bag: what the folder gives.
    if (std::system("/usr/bin/python3 -c 'import rosbag, sensor_msgs.msg, numpy' >/dev/null 2>&1") != 0) {
        if (std::getenv("SMOKESCAN_REQUIRE_READERS")) FAIL() << "python3-rosbag is not installed";
        GTEST_SKIP() << "python3-rosbag, python3-sensor-msgs or numpy is missing (scripts/setup.sh installs them)";
    }
    const fs::path pts = dir() / "ros1_lidar_pts";
    fs::remove_all(pts);
    const std::string preset = file("ros1_lidar_biased.toml",
                                    "name = \"biased\"\nbase = \"vlp16\"\n[extensions]\n[[extensions.channel]]\n"
                                    "ring = 5\nrange_offset_m = 0.2\n");
    CliRun r = cli("scan factory_smoke --sensor " + preset + " --from 38 --to 38.25 --returns dual --points " +
                   pts.string() + " --quiet");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string common = " --scene factory_smoke --sensor vlp16 --returns dual ";
    auto diagnosisOf = [&](const std::string& in, const std::string& name) {
        const fs::path out = dir() / name;
        fs::remove_all(out);
        const CliRun d = cli("diagnose --points " + in + common + "--out " + out.string());
        EXPECT_EQ(d.status, 0) << in << d.err;
        nlohmann::json j = nlohmann::json::parse(slurp(out / "diagnosis.json"));
        for (const char* k : {"pose_mismatch_m", "pose_mismatch_deg", "points", "topic"}) j.erase(k);
        return j;
    };
    const nlohmann::json folder = diagnosisOf(pts.string(), "ros1_lidar_diag_pts");
    EXPECT_EQ(folder["verdict"], "biased_channel");
    const std::string fit_folder = file("ros1_lidar_fit_pts.toml");
    ASSERT_EQ(cli("fit --points " + pts.string() + common + "--out " + fit_folder).status, 0);
    for (const std::string compression : {"none", "lz4", "bz2"}) {
        const std::string bag = (dir() / ("ros1_lidar_" + compression + ".bag")).string();
        const std::string write = "/usr/bin/python3 " SMOKESCAN_SOURCE_DIR "/tests/py/write_ros1_clouds.py " +
            pts.string() + " " + bag + " " + compression + " 8";
        ASSERT_EQ(std::system(write.c_str()), 0) << write;
        EXPECT_EQ(diagnosisOf(bag, "ros1_lidar_diag_" + compression), folder) << compression;
        const std::string fit = file("ros1_lidar_fit_" + compression + ".toml");
        r = cli("fit --points " + bag + common + "--out " + fit);
        ASSERT_EQ(r.status, 0) << r.err;
        EXPECT_EQ(slurp(fit), slurp(fit_folder)) << compression;
        const nlohmann::json report =
            nlohmann::json::parse(slurp(dir() / ("ros1_lidar_fit_" + compression + "_report.json")));
        EXPECT_EQ(report["topic"], "/points");
    }
    // A topic it does not have: named, with the PointCloud2 topics it has.
    expectBad("diagnose --points " + (dir() / "ros1_lidar_none.bag").string() + common + "--topic /cloud --out " +
                  file("ros1_lidar_d2"),
              "has no topic /cloud (PointCloud2 topics: /points)", file("ros1_lidar_d2"));
    // Rows one byte shorter than their points: refused by the layout's check, naming the message.
    const std::string short_rows = (dir() / "ros1_lidar_short.bag").string();
    const std::string write = "/usr/bin/python3 " SMOKESCAN_SOURCE_DIR "/tests/py/write_ros1_clouds.py " +
        pts.string() + " " + short_rows + " none 0 short-rows";
    ASSERT_EQ(std::system(write.c_str()), 0) << write;
    expectBad("diagnose --points " + short_rows + common + "--out " + file("ros1_lidar_d3"),
              "message 0 on /points: has rows of", file("ros1_lidar_d3"));
    // A header stamp never set (0, ROS 1's "no time"): the frame's time is not known.
    const std::string zero = (dir() / "ros1_lidar_zero.bag").string();
    const std::string write0 = "/usr/bin/python3 " SMOKESCAN_SOURCE_DIR "/tests/py/write_ros1_clouds.py " +
        pts.string() + " " + zero + " none 0 zero-stamp";
    ASSERT_EQ(std::system(write0.c_str()), 0) << write0;
    expectBad("diagnose --points " + zero + common + "--out " + file("ros1_lidar_d4"),
              "message 0 on /points: has the header stamp 0", file("ros1_lidar_d4"));
}

TEST(BagCli, ABagsFolderNameMustFitItsFileNameAndMetadata)
{
    // The folder names the bag's file (NAME_0.mcap: 7 bytes more) and metadata.yaml holds it.
    const fs::path longest = dir() / std::string(248, 'e'), too_long = dir() / std::string(249, 'e');
    const fs::path not_utf8 = dir() / "bag\xff\xfename";
    fs::remove_all(longest);
    const std::string scan = "scan plume --sensor vlp16 --from 20 --to 20 --quiet --bag ";
    expectBad(scan + too_long.string(), "would name the bag's file 256 bytes long (NAME_0.mcap, at most 255)",
              too_long.string());
    expectBad(scan + "'" + not_utf8.string() + "'", "a bag's folder name must be UTF-8 without control characters",
              not_utf8.string());
    ASSERT_EQ(cli(scan + longest.string()).status, 0);
    EXPECT_TRUE(fs::exists(longest / (std::string(248, 'e') + "_0.mcap")));
    fs::remove_all(longest);
}

TEST(BagCli, ABagOfMoreFramesThanARunKeepsIsRefusedAsItsFramesAreListed)
{
    // 200 clouds (an independent writer's) for an OS1-128 at 2048 columns: 262,144 beams a frame,
    // so 190 frames keep all the readings a run may (50 million). The 191st is refused as it is
    // listed: the bag is not read through first (each message asks the run's cancel once).
    SMOKESCAN_NEED_READERS();
    const std::string mcap = (dir() / "many_clouds.mcap").string();
    const std::string cmd = "node " + readersDir() + "/write_bag.mjs " + mcap + " 1 682 0 200";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    LidarFramesConfig cfg;
    cfg.scene = "factory_smoke";
    cfg.points = mcap;
    cfg.sensor.sensor = "os1-128";
    cfg.sensor.columns = 2048;
    int asked = 0;
    RunControl control;
    control.cancel = [&] { return ++asked < 0; };
    try {
        tallyLidarFrames(cfg, 2, control, [](const TalliedFrames&) { ADD_FAILURE() << "tallied"; });
        ADD_FAILURE() << "not refused";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("holds more than 190 frames: their readings would pass the 50000000"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_EQ(asked, 191);
}

TEST(Bag, APointCloudsLayoutIsCheckedBeforeItsPointsAreRead)
{
    PointCloud2Msg m;
    m.width = 2;
    m.point_step = 12;
    m.row_step = 24;
    m.fields = {{"x", 0, 7, 1}, {"y", 4, 7, 1}, {"z", 8, 7, 1}};
    m.data.assign(24, 0);
    EXPECT_EQ(pointCloudFileOf(m, "m").points.size(), 2u);
    // A bare message of no point (no fields, no bytes: a recorder's empty frame) reads as an
    // empty cloud, which the frames' reader leaves out; it was refused for its 0 fields.
    const PointCloudFile bare = pointCloudFileOf(PointCloud2Msg{}, "bare");
    EXPECT_TRUE(bare.points.empty() && bare.skipped == 0 && bare.fields.empty());
    auto refused = [](PointCloud2Msg bad, const std::string& says) {
        try {
            (void)pointCloudFileOf(bad, "msg 7");
            ADD_FAILURE() << says;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
            EXPECT_EQ(std::string(e.what()).rfind("msg 7", 0), 0u) << e.what();
        }
    };
    PointCloud2Msg b = m;
    b.is_bigendian = true;
    refused(b, "big-endian");
    b = m;
    b.data.resize(20);  // shorter than its row
    refused(b, "row_step");
    b = m;
    b.fields[2].offset = 10;  // z past the point's 12 bytes
    refused(b, "field 'z' (at byte 10) does not fit");
    b = m;
    b.height = 2;
    b.row_step = 12;  // rows shorter than their points
    b.data.assign(48, 0);
    refused(b, "row_step");
    b = m;
    b.fields[1].datatype = 9;
    refused(b, "field 'y' has datatype 9");
    b.fields[1].datatype = 0;
    refused(b, "field 'y' has datatype 0");
    b = m;
    b.fields.pop_back();
    refused(b, "has no field 'z'");
    b = m;
    b.width = 1u << 31;
    b.height = 4;
    refused(b, "points (at most");
    // No points in 2^32 − 1 rows of no bytes: read at once (the fuzzer's cdr-timeout: each row
    // was walked, 14 s under the sanitizers).
    b = m;
    b.width = 0;
    b.height = 0xFFFFFFFFu;
    b.row_step = 0;
    b.data.clear();
    EXPECT_EQ(pointCloudFileOf(b, "m").points.size(), 0u);
}

TEST(Bag, APointCloudsBytesNameWhatDisagreesInTheirLayout)
{
    PointCloud2Msg m;
    m.width = 2;
    m.height = 1;
    m.point_step = 12;
    m.row_step = 24;
    m.fields = {{"x", 0, 7, 1}, {"y", 4, 7, 1}, {"z", 8, 7, 1}};
    m.data.assign(24, 0);
    EXPECT_EQ(decodePointCloud2(encode(m), "msg 3").width, 2u);
    auto says = [](const PointCloud2Msg& bad) {
        try {
            (void)decodePointCloud2(encode(bad), "msg 3");
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("(read)");
    };
    PointCloud2Msg b = m;
    b.width = 1u << 31;  // more points a row than the row's bytes hold
    EXPECT_NE(says(b).find("has rows of 2147483648 points of 12 bytes (width × point_step) in 24 bytes (row_step)"),
              std::string::npos)
        << says(b);
    b = m;
    b.data.resize(20);  // fewer bytes than its rows
    EXPECT_NE(says(b).find("has 20 bytes of points, not height × row_step (1 × 24)"), std::string::npos) << says(b);
}

TEST(BagCli, ALidarsBagAndItsFramesFolderGiveTheSameDiagnosisAndFit)
{
    // A VLP-16 whose ring 3 reads 0.25 m long (the preset's extension, the planted effect), scanned
    // into a frames folder and a bag at once; each diagnosed and fitted with the plain preset.
    const fs::path pts = dir() / "lidar_bag_pts", bag = dir() / "lidar_bag";
    fs::remove_all(pts);
    fs::remove_all(bag);
    const std::string preset = file("lidar_bag_biased.toml",
                                    "name = \"biased\"\nbase = \"vlp16\"\n[extensions]\n[[extensions.channel]]\n"
                                    "ring = 3\nrange_offset_m = 0.25\n");
    CliRun r = cli("scan factory_smoke --sensor " + preset + " --from 38 --to 38.35 --returns dual --points " +
                   pts.string() + " --bag " + bag.string() + " --quiet");
    ASSERT_EQ(r.status, 0) << r.err;
    // Dual returns: the bag's `return` field tells a beam's second point from its first.
    const std::string common = " --scene factory_smoke --sensor vlp16 --returns dual ";
    std::map<std::string, nlohmann::json> diagnosis;
    for (const fs::path& in : {pts, bag, bag / "lidar_bag_0.mcap"}) {
        const fs::path out = dir() / ("lidar_bag_diag_" + in.filename().string());
        fs::remove_all(out);
        r = cli("diagnose --points " + in.string() + common + "--out " + out.string());
        ASSERT_EQ(r.status, 0) << in << r.err << r.out;
        EXPECT_NE(r.out.find("biased_channel on ring 3"), std::string::npos) << in << r.out;
        nlohmann::json j = nlohmann::json::parse(slurp(out / "diagnosis.json"));
        const bool from_bag = in != pts;
        EXPECT_EQ(j["pose_mismatch_m"].is_null(), from_bag) << in;
        EXPECT_EQ(slurp(out / "report.md").find("carry no recorded pose") != std::string::npos, from_bag);
        // What was read, in the JSON and the report: the path given, and a bag's topic.
        EXPECT_EQ(j["points"], in.string());
        EXPECT_EQ(j["topic"], from_bag ? nlohmann::json("/points") : nlohmann::json()) << in;
        EXPECT_NE(
            slurp(out / "report.md").find("frames read from " + in.string() + (from_bag ? " (topic /points)." : ".")),
            std::string::npos)
            << in;
        for (const char* k : {"pose_mismatch_m", "pose_mismatch_deg", "points", "topic"}) j.erase(k);
        diagnosis[in.string()] = j;
        EXPECT_EQ(slurp(out / "lidar.toml"), slurp(dir() / "lidar_bag_diag_lidar_bag_pts" / "lidar.toml"));
    }
    EXPECT_EQ(diagnosis[bag.string()], diagnosis[pts.string()]);
    EXPECT_EQ(diagnosis[(bag / "lidar_bag_0.mcap").string()], diagnosis[pts.string()]);
    // The fit reads the bag's intensities as the folder's, and its report names what it read.
    for (const fs::path& in : {pts, bag}) {
        const std::string out = file("lidar_bag_fit_" + in.filename().string() + ".toml");
        r = cli("fit --points " + in.string() + common + "--out " + out + " --report " + out + ".json");
        ASSERT_EQ(r.status, 0) << r.err;
        const nlohmann::json fit = nlohmann::json::parse(slurp(out + ".json"));
        EXPECT_EQ(fit["points"], in.string());
        EXPECT_EQ(fit["topic"], in == bag ? nlohmann::json("/points") : nlohmann::json()) << in;
    }
    EXPECT_EQ(slurp(file("lidar_bag_fit_lidar_bag.toml")), slurp(file("lidar_bag_fit_lidar_bag_pts.toml")));
    // The bag's .mcap copied alone into a folder: neither a frames folder nor a rosbag2 folder.
    const fs::path lone = dir() / "lidar_bag_lone";
    fs::remove_all(lone);
    fs::create_directories(lone);
    fs::copy_file(bag / "lidar_bag_0.mcap", lone / "lidar_bag_0.mcap");
    expectBad("diagnose --points " + lone.string() + common + "--out " + file("lidar_bag_d6"),
              "no metadata.yaml (a rosbag2 folder): give --points its file " + (lone / "lidar_bag_0.mcap").string(),
              file("lidar_bag_d6"));
    fs::copy_file(bag / "lidar_bag_0.mcap", lone / "B.MCAP");  // several, any case: each named
    expectBad("diagnose --points " + lone.string() + common + "--topic /points --out " + file("lidar_bag_d7"),
              "give --points one of its 2 .mcap files (" + (lone / "B.MCAP").string() + ", " +
                  (lone / "lidar_bag_0.mcap").string() + ")",
              file("lidar_bag_d7"));
    // A path whose bytes are not UTF-8 (a link to the bag): named in the JSON and the report as \xNN.
    const fs::path odd = dir() / "lidar_bag_\xff_odd";  // the byte mid-name: all of it named
    fs::remove(odd);
    fs::create_directory_symlink(fs::absolute(bag), odd);
    const fs::path odd_out = dir() / "lidar_bag_diag_odd";
    fs::remove_all(odd_out);
    r = cli("diagnose --points " + odd.string() + common + "--out " + odd_out.string());
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string named = (dir() / "lidar_bag_\\xFF_odd").string();
    EXPECT_EQ(nlohmann::json::parse(slurp(odd_out / "diagnosis.json"))["points"], named);
    EXPECT_NE(slurp(odd_out / "report.md").find("frames read from " + named + " (topic /points)."), std::string::npos);
    // A topic that is not there, --topic with a folder, a bag whose files an output would replace.
    expectBad("diagnose --points " + bag.string() + common + "--topic /nope --out " + file("lidar_bag_d1"),
              "has no topic /nope", file("lidar_bag_d1"));
    expectBad("diagnose --points " + pts.string() + common + "--topic /points --out " + file("lidar_bag_d2"),
              "--topic: names a bag's topic", file("lidar_bag_d2"));
    // Frames closer than the sensor's span: another rate.
    const fs::path fast = dir() / "lidar_bag_20hz";
    fs::remove_all(fast);
    ASSERT_EQ(cli("scan factory_smoke --sensor vlp16 --rate 20 --from 38 --to 38.2 --bag " + fast.string() + " --quiet")
                  .status,
              0);
    expectBad(
        "diagnose --points " + fast.string() + " --scene factory_smoke --sensor vlp16 --out " + file("lidar_bag_d4"),
        "before it ends (the vlp16's frame spans 0.0999", file("lidar_bag_d4"));
    // A cancel asked while the bag is read stops it as a cancel, whether the topic is named or not.
    for (const std::string topic : {"", "/points"}) {
        LidarFramesConfig cfg;
        cfg.scene = "factory_smoke";
        cfg.points = bag.string();
        cfg.sensor.sensor = "vlp16";
        cfg.sensor.returns = "dual";
        cfg.topic = topic;
        int asked = 0, used = 0;
        RunControl control;
        control.cancel = [&] { return ++asked > 3; };
        EXPECT_THROW(tallyLidarFrames(cfg, 2, control, [&](const TalliedFrames&) { ++used; }), Cancelled) << topic;
        EXPECT_EQ(asked, 4) << topic;  // stopped at once
        EXPECT_EQ(used, 0);
    }
    const std::string meta = slurp(bag / "metadata.yaml");
    expectBad("fit --points " + bag.string() + common + "--out " + file("lidar_bag_f3.toml") + " --report " +
                  (bag / "metadata.yaml").string(),
              "metadata.yaml", file("lidar_bag_f3.toml"));
    // The same through the bag's .mcap: its folder is the bag's.
    expectBad("fit --points " + (bag / "lidar_bag_0.mcap").string() + common + "--out " + file("lidar_bag_f4.toml") +
                  " --report " + (bag / "metadata.yaml").string(),
              "lies in the frames' folder", file("lidar_bag_f4.toml"));
    // And through a symbolic link to the .mcap, elsewhere: the folder is where the file is.
    const fs::path link = dir() / "lidar_bag_link.mcap";
    fs::remove(link);
    fs::create_symlink(fs::absolute(bag / "lidar_bag_0.mcap"), link);
    expectBad("fit --points " + link.string() + common + "--out " + file("lidar_bag_f5.toml") + " --report " +
                  (bag / "metadata.yaml").string(),
              "lies in the frames' folder", file("lidar_bag_f5.toml"));
    EXPECT_EQ(slurp(bag / "metadata.yaml"), meta);
    // Frames stamped outside the scene's time (factory_smoke: 0 to 48 s), as a recording's
    // wall-clock stamps would be: scanned in the same room with a longer time line (scan refuses
    // times outside its scene's).
    const fs::path late = dir() / "lidar_bag_late";
    fs::remove_all(late);
    std::string longer = slurp("scenes/factory_smoke.toml");
    ASSERT_NE(longer.find("t_end_s = 48\n"), std::string::npos);
    longer.replace(longer.find("t_end_s = 48\n"), 13, "t_end_s = 80\n");
    const std::string longer_scene = file("factory_smoke_80s.toml", longer);
    expectBad("scan factory_smoke --sensor vlp16 --from 60 --to 60.2 --bag " + late.string(),
              "--from: 60 s is after the scene's end, 48 s", late.string());
    ASSERT_EQ(
        cli("scan " + longer_scene + " --sensor vlp16 --from 60 --to 60.2 --bag " + late.string() + " --quiet").status,
        0);
    expectBad(
        "diagnose --points " + late.string() + " --scene factory_smoke --sensor vlp16 --out " + file("lidar_bag_d5"),
        "message 0 on /points: runs from 60 to 60.0999", file("lidar_bag_d5"));
}
