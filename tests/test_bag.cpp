// ROS 2 bags (bag/): CDR against its byte layout worked out by hand from the specification, and
// the bags `scan --bag` writes read back by independent readers (Foxglove's @mcap/core and
// @foxglove/rosmsg2-serialization, under node: tests/js/read_bag.mjs, installed by
// scripts/setup_readers.sh) and compared value by value with the laser log of the same run.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <nlohmann/json.hpp>
#include <sstream>

#include "bag_readers.hpp"
#include "cli_run.hpp"
#include "smokescan/bag/bag_input.hpp"
#include "smokescan/bag/cdr.hpp"
#include "smokescan/bag/mcap_reader.hpp"
#include "smokescan/bag/mcap_writer.hpp"
#include "smokescan/bag/ros_messages.hpp"
#include "smokescan/bag/scan_messages.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/fit/bag_saturation.hpp"
#include "smokescan/io/image.hpp"
#include "smokescan/lidar/point_cloud_io.hpp"
#include "smokescan/sensor_config/lms200.hpp"
#include "smokescan/sensor_config/urg04lx.hpp"

using namespace smokescan;
using namespace smokescan::test;

namespace {

template <class T>
T at(const std::vector<uint8_t>& b, size_t payload_offset)
{
    T v;
    std::memcpy(&v, b.data() + 4 + payload_offset, sizeof v);
    return v;
}

}  // namespace

TEST(Cdr, ALaserScanIsLaidOutAsTheSpecificationSays)
{
    LaserScanMsg m;
    m.header.stamp = {1, 2};
    m.header.frame_id = "ab";
    m.angle_min = 0.5f;
    m.range_max = 5.6f;
    m.ranges = {1.0f};
    const std::vector<uint8_t> b = encode(m);
    // Encapsulation 00 01 00 00; sec 0–3, nanosec 4–7, frame_id's length 3 at 8, "ab\0" at 12–14,
    // one byte of padding, seven float32 at 16–43, ranges' count at 44 and its value at 48,
    // intensities' count 0 at 52: 56 bytes after the header.
    ASSERT_EQ(b.size(), 60u);
    EXPECT_EQ(b[0], 0);
    EXPECT_EQ(b[1], 1);
    EXPECT_EQ(at<int32_t>(b, 0), 1);
    EXPECT_EQ(at<uint32_t>(b, 4), 2u);
    EXPECT_EQ(at<uint32_t>(b, 8), 3u);
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(b.data() + 4 + 12), 3), std::string("ab\0", 3));
    EXPECT_EQ(b[4 + 15], 0);
    EXPECT_EQ(at<float>(b, 16), 0.5f);
    EXPECT_EQ(at<float>(b, 16 + 6 * 4), 5.6f);
    EXPECT_EQ(at<uint32_t>(b, 44), 1u);
    EXPECT_EQ(at<float>(b, 48), 1.0f);
    EXPECT_EQ(at<uint32_t>(b, 52), 0u);
    const LaserScanMsg back = decodeLaserScan(b, "scan");
    EXPECT_EQ(back.header.frame_id, "ab");
    EXPECT_EQ(back.ranges, m.ranges);
    EXPECT_EQ(back.range_max, 5.6f);
}

TEST(Cdr, DoublesAreAlignedToEightBytesFromThePayloadsStart)
{
    TfMsg m;
    TransformStampedMsg t;
    t.header.frame_id = "m";
    t.child_frame_id = "s";
    t.translation[0] = 1.5;
    t.rotation[3] = -1;
    m.transforms = {t};
    const std::vector<uint8_t> b = encode(m);
    // count 0–3; sec 4, nanosec 8; "m" length 2 at 12, bytes 16–17; "s" (aligned to 20) length at
    // 20, bytes 24–25; the first float64 aligned to 32: seven of them end at 88.
    ASSERT_EQ(b.size(), 4u + 88u);
    EXPECT_EQ(at<uint32_t>(b, 0), 1u);
    EXPECT_EQ(at<uint32_t>(b, 20), 2u);
    EXPECT_EQ(at<double>(b, 32), 1.5);
    EXPECT_EQ(at<double>(b, 32 + 6 * 8), -1.0);
    EXPECT_EQ(decodeTf(b, "tf").transforms.at(0).child_frame_id, "s");
}

TEST(Cdr, BadBytesAreOneLineErrorsNamingTheMessage)
{
    LaserScanMsg m;
    m.header.frame_id = "laser";
    m.ranges = {1, 2, 3};
    const std::vector<uint8_t> good = encode(m);
    auto error = [](const std::vector<uint8_t>& b) {
        try {
            (void)decodeLaserScan(b, "x.mcap: message 3 on /scan");
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("decoded");
    };
    for (size_t n : {size_t(0), size_t(3), size_t(10), good.size() - 1}) {
        const std::string e = error(std::vector<uint8_t>(good.begin(), good.begin() + long(n)));
        EXPECT_NE(e.find("x.mcap: message 3 on /scan"), std::string::npos) << n << ": " << e;
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    }
    std::vector<uint8_t> big = good;
    big[1] = 0;  // big-endian encapsulation
    EXPECT_NE(error(big).find("big-endian"), std::string::npos);
    std::vector<uint8_t> huge = good;
    const uint32_t claim = 0x40000000;  // the ranges' count: a billion floats in 60 bytes
    std::memcpy(huge.data() + 4 + 48, &claim, 4);
    EXPECT_NE(error(huge).find("ends at byte"), std::string::npos) << error(huge);
    std::vector<uint8_t> longer = good;
    longer.insert(longer.end(), 8, 0);
    EXPECT_NE(error(longer).find("bytes left after the message"), std::string::npos) << error(longer);
    EXPECT_THROW((void)RosTime::fromSeconds(-1), Error);
    EXPECT_THROW((void)RosTime::fromSeconds(NAN), Error);
    EXPECT_EQ(RosTime::fromSeconds(1.5).nanoseconds(), 1500000000ull);
    EXPECT_EQ(RosTime::fromSeconds(0.1).nanosec, 100000000u);
    EXPECT_EQ(RosTime::fromSeconds(2.0 / 3).nanosec, 666666667u);  // rounded, not truncated
    const RosTime carry = RosTime::fromSeconds(0.9999999996);
    EXPECT_EQ(carry.sec, 1);
    EXPECT_EQ(carry.nanosec, 0u);
}

namespace {

/// The laser log's scans: time and raw values in mm.
std::vector<std::pair<double, std::vector<long long>>> logScans(const std::string& path)
{
    std::vector<std::pair<double, std::vector<long long>>> scans;
    std::istringstream in(slurp(path));
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream f(line);
        double t, angle;
        long long v;
        f >> t;
        scans.push_back({t, {}});
        while (f >> angle >> v) scans.back().second.push_back(v);
    }
    return scans;
}

}  // namespace

TEST(BagCli, AScanBagIsReadByIndependentReadersAsTheLogOfTheSameRun)
{
    SMOKESCAN_NEED_READERS();
    const std::string log = file("bag_run.log"), bag = (dir() / "bag_run").string();
    fs::remove_all(bag);
    // The URG-04LX in bocas's thick smoke: ranges and each kind of error value.
    const CliRun r =
        cli("scan bocas --from 100 --to 104 --rate 2 --model physical --quiet --out " + log + " --bag " + bag);
    ASSERT_EQ(r.status, 0) << r.err;
    ASSERT_TRUE(fs::exists(fs::path(bag) / "metadata.yaml"));
    const std::string meta = slurp(fs::path(bag) / "metadata.yaml");
    EXPECT_NE(meta.find("storage_identifier: mcap"), std::string::npos) << meta;
    EXPECT_NE(meta.find("- bag_run_0.mcap"), std::string::npos) << meta;
    EXPECT_NE(meta.find("type: sensor_msgs/msg/LaserScan"), std::string::npos) << meta;
    // rosbag2's metadata: 9 scans and the mount, from 100 s for 4 s.
    EXPECT_NE(meta.find("message_count: 10"), std::string::npos) << meta;
    EXPECT_NE(meta.find("nanoseconds_since_epoch: 100000000000"), std::string::npos) << meta;
    EXPECT_NE(meta.find("nanoseconds: 4000000000"), std::string::npos) << meta;
    const nlohmann::json j = readIndependently((fs::path(bag) / "bag_run_0.mcap").string());
    EXPECT_TRUE(j["problems"].empty()) << j["problems"];
    EXPECT_EQ(j["profile"], "ros2");
    EXPECT_EQ(j["dataEndCrc"], j["dataCrc"]);
    EXPECT_NE(j["dataCrc"], 0);
    EXPECT_EQ(j["compression"], nlohmann::json::array({"zstd"}));
    EXPECT_EQ(j["chunks"], j["chunkIndexes"]);
    EXPECT_EQ(j["streamedMessages"].get<int>(), std::stoi(j["messageCount"].get<std::string>()));
    const auto scans = logScans(log);
    ASSERT_EQ(scans.size(), 9u);
    size_t k = 0, codes = 0, inf = 0, nan = 0;
    for (const auto& m : j["messages"]) {
        if (m["topic"] != "/scan") continue;
        ASSERT_LT(k, scans.size());
        const auto& [t, values] = scans[k];
        EXPECT_EQ(m["schema"], "sensor_msgs/msg/LaserScan");
        EXPECT_EQ(m["messageEncoding"], "cdr");
        EXPECT_EQ(m["sequence"], k);
        EXPECT_EQ(std::stoull(m["logTime"].get<std::string>()), (unsigned long long)std::llround(t * 1e9));
        const auto& msg = m["message"];
        EXPECT_EQ(msg["header"]["frame_id"], "hokuyo");
        EXPECT_EQ(msg["header"]["stamp"]["sec"].get<long long>() * 1000000000LL +
                      msg["header"]["stamp"]["nanosec"].get<long long>(),
                  std::llround(t * 1e9));
        // SCIP 2.0's steps 44…725 at 360°/1024 from step 384 ahead; 20 mm … 5.6 m.
        EXPECT_FLOAT_EQ(msg["angle_min"].get<float>(), float((44 - 384) * 2 * M_PI / 1024));
        EXPECT_FLOAT_EQ(msg["angle_increment"].get<float>(), float(2 * M_PI / 1024));
        EXPECT_FLOAT_EQ(msg["angle_max"].get<float>(), float((725 - 384) * 2 * M_PI / 1024));
        EXPECT_FLOAT_EQ(msg["range_min"].get<float>(), 0.02f);
        EXPECT_FLOAT_EQ(msg["range_max"].get<float>(), 5.6f);
        EXPECT_FLOAT_EQ(msg["scan_time"].get<float>(), 0.1f);
        EXPECT_EQ(msg["time_increment"].get<float>(), 0.0f);
        EXPECT_TRUE(msg["intensities"].empty());
        const auto& ranges = msg["ranges"];
        ASSERT_EQ(ranges.size(), values.size());
        for (size_t b = 0; b < values.size(); ++b) {
            const double got = number(ranges[b]);
            const long long v = values[b];
            if (v >= 20) {
                EXPECT_EQ(float(got), float(double(v) * 0.001)) << k << " " << b;
                continue;
            }
            ++codes;
            if (v == 0 || v == 1) {  // no return, too weak: nothing in range (REP 117: +Inf)
                EXPECT_TRUE(std::isinf(got) && got > 0) << v;
                ++inf;
            } else {  // the two waves disagree, a saturated receiver: a failed measurement (NaN)
                EXPECT_TRUE(std::isnan(got)) << v;
                ++nan;
            }
        }
        ++k;
    }
    EXPECT_EQ(k, scans.size());
    EXPECT_GT(inf, 50u) << "the run should hold beams the smoke stopped";
    EXPECT_GT(nan, 0u) << "and a failed measurement (this seed has one)";
    EXPECT_EQ(inf + nan, codes);
}

TEST(BagCli, ARobotsPoseGoesOnTfAndTheSensorsMountOnTfStatic)
{
    SMOKESCAN_NEED_READERS();
    const std::string bag = (dir() / "bag_maze").string();
    fs::remove_all(bag);
    const CliRun r = cli("scan maze --from 0 --to 12 --rate 0.5 --quiet --bag " + bag);
    ASSERT_EQ(r.status, 0) << r.err;
    const nlohmann::json j = readIndependently((fs::path(bag) / "bag_maze_0.mcap").string());
    int tf = 0, statics = 0, scans = 0;
    for (const auto& m : j["messages"]) {
        const double t = double(std::stoull(m["logTime"].get<std::string>())) * 1e-9;
        if (m["topic"] == "/tf_static") {
            ++statics;
            const auto& x = m["message"]["transforms"][0];
            EXPECT_EQ(x["header"]["frame_id"], "p2dx");
            EXPECT_EQ(x["child_frame_id"], "sick");
            EXPECT_DOUBLE_EQ(x["transform"]["translation"]["z"].get<double>(), 0.3);
            // yaw −90°: (0, 0, −sin 45°, cos 45°), up to the quaternion's sign
            const double s = x["transform"]["rotation"]["w"].get<double>() > 0 ? 1 : -1;
            EXPECT_NEAR(s * x["transform"]["rotation"]["z"].get<double>(), -M_SQRT1_2, 1e-12);
            EXPECT_NEAR(s * x["transform"]["rotation"]["w"].get<double>(), M_SQRT1_2, 1e-12);
        } else if (m["topic"] == "/tf") {
            ++tf;
            const auto& x = m["message"]["transforms"][0];
            EXPECT_EQ(x["header"]["frame_id"], "map");
            EXPECT_EQ(x["child_frame_id"], "p2dx");
            // maze.toml: from (−2, 0) at 0 s to (3.75, 0) at 12 s, linearly.
            EXPECT_NEAR(x["transform"]["translation"]["x"].get<double>(), -2 + 5.75 * t / 12, 1e-9) << t;
            EXPECT_NEAR(x["transform"]["translation"]["y"].get<double>(), 0, 1e-9) << t;
        } else if (m["topic"] == "/scan") {
            ++scans;
            EXPECT_EQ(m["message"]["header"]["frame_id"], "sick");
            EXPECT_EQ(m["message"]["ranges"].size(), 361u);  // the LMS200 at 0.5°
        }
    }
    EXPECT_EQ(statics, 1);
    EXPECT_EQ(tf, 7);
    EXPECT_EQ(scans, 7);
}

TEST(BagCli, ABagThatCannotBeWrittenLeavesNothing)
{
    const std::string log = file("bag_bad.log"), taken = (dir() / "bag_taken").string();
    fs::create_directories(taken);
    std::ofstream(fs::path(taken) / "x") << "mine";
    expectBad("scan bocas --to 1 --out " + log + " --bag " + taken, "--bag", log);
    EXPECT_EQ(slurp(fs::path(taken) / "x"), "mine");
    expectBad("scan bocas --sensor vlp16 --to 0.1 --points-format ply --bag " + (dir() / "bag_bad_lidar").string(),
              "--points-format", (dir() / "bag_bad_lidar").string());
    expectBad("scan bocas --to 1", "--out FILE, --bag DIR", log);
}

namespace {

/// The scans the independent writers make (tests/js/write_bag.mjs, tests/py/write_ros1_bag.py):
/// scan k at 10 + 0.5 k s, beam i at 0.5 + 0.001 (i + k) m, beam 3 +Inf, beam 5 NaN.
void expectTheWritersRule(const BagLaserScans& b, size_t scans, const std::string& label)
{
    ASSERT_EQ(b.scans.size(), scans) << label;
    for (size_t k = 0; k < b.scans.size(); ++k) {
        const LaserScanMsg& s = b.scans[k];
        EXPECT_EQ(s.header.stamp.nanoseconds(), 10000000000ull + k * 500000000ull);
        EXPECT_EQ(s.header.frame_id, "laser");
        EXPECT_EQ(s.angle_increment, 0.006135923322290182f);
        ASSERT_EQ(s.ranges.size(), 682u);
        for (size_t i = 0; i < s.ranges.size(); ++i) {
            if (i == 3)
                EXPECT_TRUE(std::isinf(s.ranges[i]) && s.ranges[i] > 0);
            else if (i == 5)
                EXPECT_TRUE(std::isnan(s.ranges[i]));
            else
                ASSERT_EQ(s.ranges[i], float(0.5 + 0.001 * double(i + k))) << label << " " << k << " " << i;
        }
    }
}

}  // namespace

TEST(BagCli, ReadsTheLaserScansAnIndependentWriterWrote)
{
    SMOKESCAN_NEED_READERS();
    const std::string mcap = (dir() / "independent.mcap").string();
    const std::string cmd = "node " + readersDir() + "/write_bag.mjs " + mcap + " 40 682";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    const BagLaserScans b = readBagLaserScans(mcap, "");
    EXPECT_EQ(b.topic, "/front/scan");  // the only LaserScan topic, beside /tf
    expectTheWritersRule(b, 40, "mcap");
    // As the URG-04LX's log: metres to its millimetres, +Inf its no-return code, NaN a failed one.
    const RecordedLog log = recordedLogOf(b, urg04lx());
    EXPECT_EQ(log.unit_m, 0.001);
    EXPECT_DOUBLE_EQ(log.scans[2].time_s, 11.0);
    EXPECT_EQ(log.scans[2].range[0], 502.0);
    EXPECT_EQ(log.scans[2].range[3], double(urg_code::kNoReturn));
    EXPECT_EQ(log.scans[2].range[5], double(urg_code::kTwoWaveDifference));
    EXPECT_NEAR(log.scans[2].angle_rad[1] - log.scans[2].angle_rad[0], 2 * M_PI / 1024, 1e-7);
    // The topic named, and one of another type.
    EXPECT_EQ(readBagLaserScans(mcap, "/front/scan").scans.size(), 40u);
    try {
        (void)readBagLaserScans(mcap, "/tf");
        FAIL() << "/tf read as LaserScans";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("topic /tf is tf2_msgs/msg/TFMessage, not sensor_msgs/msg/LaserScan"),
                  std::string::npos)
            << e.what();
    }
}

TEST(BagCli, ABagAndTheLogOfTheSameRunGiveTheSameFitAndDiagnosis)
{
    const std::string log = file("same_run.log"), sat = file("same_run.csv"), bag = (dir() / "same_run").string();
    fs::remove_all(bag);
    ASSERT_EQ(cli("scan bocas --from 80 --to 130 --rate 2 --quiet --out " + log + " --bag " + bag +
                  " --saturation-out " + sat)
                  .status,
              0);
    const std::string common = " --saturation " + sat + " --scene bocas";
    ASSERT_EQ(cli("fit --laser " + log + common + " --out " + file("same_a.toml")).status, 0);
    const CliRun b = cli("fit --bag " + bag + common + " --out " + file("same_b.toml"));
    ASSERT_EQ(b.status, 0) << b.err;
    auto withoutSources = [](const std::string& path) {
        nlohmann::json j = nlohmann::json::parse(slurp(path));
        j.erase("sources");
        return j;
    };
    EXPECT_EQ(withoutSources(file("same_a_report.json")), withoutSources(file("same_b_report.json")));
    EXPECT_EQ(nlohmann::json::parse(slurp(file("same_b_report.json")))["sources"]["laser"], bag + " /scan");
    const std::string da = (dir() / "same_da").string(), db = (dir() / "same_db").string();
    fs::remove_all(da);
    fs::remove_all(db);
    ASSERT_EQ(cli("diagnose --laser " + log + common + " --out " + da).status, 0);
    const CliRun d = cli("diagnose --bag " + bag + " --topic /scan" + common + " --out " + db);
    ASSERT_EQ(d.status, 0) << d.err;
    auto diagnosis = [](const std::string& folder) {
        nlohmann::json j = nlohmann::json::parse(slurp(fs::path(folder) / "diagnosis.json"));
        j.erase("inputs");
        return j;
    };
    EXPECT_EQ(diagnosis(da), diagnosis(db));
    // One source of scans, and a topic only with a bag.
    expectBad("fit --laser " + log + " --bag " + bag + common + " --out " + file("same_c.toml"), "--bag",
              file("same_c.toml"));
    expectBad("fit --laser " + log + " --topic /scan" + common + " --out " + file("same_c.toml"), "--topic",
              file("same_c.toml"));
    expectBad("fit" + common + " --out " + file("same_c.toml"), "--laser LOG or --bag PATH", file("same_c.toml"));
    expectBad("fit --bag " + bag + " --topic /tf_static" + common + " --out " + file("same_c.toml"),
              "topic /tf_static is tf2_msgs/msg/TFMessage", file("same_c.toml"));
    expectBad("fit --bag " + bag + " --topic /nope" + common + " --out " + file("same_c.toml"),
              "has no topic /nope (LaserScan topics: /scan)", file("same_c.toml"));
}

namespace {

/// A small bag's MCAP bytes: /scan LaserScans at `stamps_s` (and a /tf channel), in chunks of
/// `chunk_bytes`.
std::vector<uint8_t> scanMcap(const std::vector<double>& stamps_s, size_t chunk_bytes = 1 << 20)
{
    std::ostringstream o;
    McapWriterConfig cfg;
    cfg.chunk_bytes = chunk_bytes;
    McapWriter w(o, cfg);
    const uint16_t scan =
        w.addChannel(w.addSchema(kLaserScanType.name, "ros2msg", kLaserScanType.definition), "/scan", "cdr");
    (void)w.addChannel(w.addSchema(kTfType.name, "ros2msg", kTfType.definition), "/tf", "cdr");
    for (double t : stamps_s) {
        LaserScanMsg m;
        m.header.stamp = RosTime::fromSeconds(t);
        m.header.frame_id = "laser";
        m.ranges.assign(100, float(t));
        w.write(scan, m.header.stamp.nanoseconds(), m.header.stamp.nanoseconds(), encode(m));
    }
    w.finish();
    const std::string s = o.str();
    return {s.begin(), s.end()};
}

std::string mcapError(const std::vector<uint8_t>& b)
{
    try {
        (void)readMcapBytes(b, "bad.mcap", [](const McapChannel&, McapMessage&&) {});
    } catch (const Error& e) {
        return e.what();
    }
    return "read";
}

std::string bagError(const std::string& path, const std::string& topic = "")
{
    try {
        (void)readBagLaserScans(path, topic);
    } catch (const Error& e) {
        return e.what();
    }
    return "read";
}

std::string writeBytes(const std::string& name, const std::vector<uint8_t>& b)
{
    const std::string p = file(name);
    std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
    return p;
}

}  // namespace

TEST(Bag, WhatTheWriterWritesIsReadBackInOrderAcrossChunks)
{
    std::vector<double> t;
    for (int k = 0; k < 300; ++k) t.push_back(1 + 0.1 * k);
    const std::vector<uint8_t> b = scanMcap(t, 2000);  // about 4 messages a chunk
    std::vector<double> seen;
    const auto channels = readMcapBytes(b, "good.mcap", [&](const McapChannel& ch, McapMessage&& m) {
        EXPECT_EQ(ch.topic, "/scan");
        EXPECT_EQ(m.sequence, seen.size());
        seen.push_back(double(decodeLaserScan(m.data, "m").ranges.at(7)));
        EXPECT_EQ(m.log_time_ns, RosTime::fromSeconds(t[seen.size() - 1]).nanoseconds());
    });
    ASSERT_EQ(seen.size(), t.size());
    for (size_t k = 0; k < t.size(); ++k) EXPECT_EQ(seen[k], double(float(t[k])));
    ASSERT_EQ(channels.size(), 2u);
    EXPECT_EQ(channels.at(1).schema_name, "sensor_msgs/msg/LaserScan");
    EXPECT_EQ(channels.at(2).topic, "/tf");
}

TEST(Bag, DamagedOrWrongBagsAreOneLineErrorsNamingTheFileAndRecord)
{
    const std::vector<uint8_t> good = scanMcap({1, 2, 3});
    // The first chunk follows the magic (8) and the Header (9 + "ros2" 8 + "smokescan" 13) at 38;
    // its compression's name at 38 + 9 + 28 + 4, its compressed records from 91.
    ASSERT_EQ(good[38], 0x06);
    ASSERT_EQ(std::string(good.begin() + 79, good.begin() + 83), "zstd");
    struct Case {
        std::vector<uint8_t> bytes;
        std::string needle;
    };
    std::vector<Case> cases;
    cases.push_back({{good.begin(), good.begin() + 200}, "does not end with MCAP's magic"});
    {
        std::vector<uint8_t> cut(good.begin(), good.begin() + 120);  // inside the chunk, magic re-added
        cut.insert(cut.end(), good.end() - 8, good.end());
        cases.push_back({cut, "record at byte 38 (opcode 0x06): claims"});
    }
    {
        std::vector<uint8_t> b = good;
        std::memcpy(b.data() + 79, "brot", 4);
        cases.push_back({b, "uses the compression 'brot'"});
    }
    {
        std::vector<uint8_t> b = good;
        b[100] ^= 0x55;  // inside the compressed records
        const std::string e = mcapError(b);
        EXPECT_TRUE(e.find("could not be decompressed") != std::string::npos ||
                    e.find("fails its CRC") != std::string::npos || e.find("decompresses to") != std::string::npos)
            << e;
        EXPECT_NE(e.find("bad.mcap: record at byte 38"), std::string::npos) << e;
    }
    {
        std::vector<uint8_t> b = good;
        b[30] ^= 1;  // the Header's library name: only the data section's CRC sees it
        cases.push_back({b, "data section's CRC wrong"});
    }
    {
        std::vector<uint8_t> b = good;
        const uint64_t huge = uint64_t(1) << 40;
        std::memcpy(b.data() + 38 + 9 + 16, &huge, 8);  // the chunk's uncompressed size
        cases.push_back({b, "over the limit"});
    }
    cases.push_back({std::vector<uint8_t>(64, 'x'), "is not an MCAP file"});
    cases.push_back({{}, "is too short"});
    for (const Case& c : cases) {
        const std::string e = mcapError(c.bytes);
        EXPECT_NE(e.find(c.needle), std::string::npos) << c.needle << " | " << e;
        EXPECT_NE(e.find("bad.mcap"), std::string::npos) << e;
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    }
    // A bag's topics and stamps.
    EXPECT_NE(bagError(writeBytes("empty.mcap", scanMcap({}))).find("has no messages on /scan"), std::string::npos)
        << bagError(writeBytes("empty.mcap", scanMcap({})));
    EXPECT_NE(bagError(writeBytes("back.mcap", scanMcap({1, 3, 2}))).find("stamps must increase"), std::string::npos);
    EXPECT_NE(bagError(writeBytes("same.mcap", scanMcap({1, 1}))).find("message 1 on /scan"), std::string::npos);
    EXPECT_NE(bagError(file("no_such.mcap")).find("does not exist"), std::string::npos);
    // rosbag2 folders.
    const fs::path folder = dir() / "bad_bag";
    fs::remove_all(folder);
    fs::create_directories(folder);
    EXPECT_NE(bagError(folder.string()).find("without metadata.yaml"), std::string::npos);
    auto meta = [&](const std::string& storage, const std::string& file) {
        std::ofstream(folder / "metadata.yaml")
            << "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: " << storage
            << "\n  relative_file_paths:\n    - " << file << "\n";
        return bagError(folder.string());
    };
    EXPECT_NE(meta("sqlite3", "x.db3").find("storage_identifier: 'sqlite3'"), std::string::npos);
    EXPECT_NE(meta("mcap", "../../etc/passwd").find("is not inside the bag"), std::string::npos);
    EXPECT_NE(meta("mcap", "missing_0.mcap").find("does not exist"), std::string::npos)
        << meta("mcap", "missing_0.mcap");
    // A link to a sibling folder whose name extends the bag's leads outside it.
    const fs::path sibling = dir() / "bad_bag2";
    fs::create_directories(sibling);
    (void)writeBytes("bad_bag2/x.mcap", scanMcap({1, 2}));
    fs::remove(folder / "link.mcap");
    fs::create_symlink(sibling / "x.mcap", folder / "link.mcap");
    EXPECT_NE(meta("mcap", "link.mcap").find("leads outside the bag"), std::string::npos) << meta("mcap", "link.mcap");
    std::ofstream(folder / "metadata.yaml") << "rosbag2_bagfile_information: [unclosed\n";
    EXPECT_NE(bagError(folder.string()).find("metadata.yaml:"), std::string::npos) << bagError(folder.string());
}

namespace {

/// One field of a PointCloud2 point, read by its declared offset and datatype (from the JSON the
/// independent reader printed).
double fieldValue(const nlohmann::json& fields, const std::string& name, const std::string& bytes, size_t at)
{
    for (const auto& f : fields) {
        if (f["name"] != name) continue;
        const size_t o = at + f["offset"].get<size_t>();
        switch (f["datatype"].get<int>()) {
        case 2:
            return double(uint8_t(bytes[o]));
        case 4: {
            uint16_t v;
            std::memcpy(&v, bytes.data() + o, 2);
            return v;
        }
        case 7: {
            float v;
            std::memcpy(&v, bytes.data() + o, 4);
            return v;
        }
        default:
            ADD_FAILURE() << name << ": datatype " << f["datatype"];
        }
    }
    ADD_FAILURE() << "no field " << name;
    return NAN;
}

}  // namespace

TEST(BagCli, ALidarsFramesArePointCloudsWithTheDriversFieldsAsInItsPcdFiles)
{
    SMOKESCAN_NEED_READERS();
    const fs::path points = dir() / "bag_lidar_points", bag = dir() / "bag_lidar";
    fs::remove_all(points);
    fs::remove_all(bag);
    const CliRun r = cli("scan plume --sensor vlp16 --from 10 --to 10.25 --returns dual --points " + points.string() +
                         " --bag " + bag.string());
    ASSERT_EQ(r.status, 0) << r.err;
    const nlohmann::json j = readIndependently((bag / "bag_lidar_0.mcap").string());
    size_t k = 0, smoke = 0, second = 0;
    for (const auto& m : j["messages"]) {
        if (m["topic"] != "/points") continue;
        EXPECT_EQ(m["schema"], "sensor_msgs/msg/PointCloud2");
        char name[32];
        std::snprintf(name, sizeof name, "%06zu.pcd", k);
        const PointCloudFile pcd = readPointCloud((points / name).string());
        const auto& msg = m["message"];
        EXPECT_EQ(msg["header"]["frame_id"], "vlp16");
        EXPECT_EQ(std::stoull(m["logTime"].get<std::string>()), (unsigned long long)std::llround(pcd.start_s * 1e9));
        EXPECT_EQ(msg["height"], 1);
        EXPECT_EQ(msg["is_bigendian"], false);
        const size_t step = msg["point_step"].get<size_t>();
        const std::string data = base64(msg["data"].get<std::string>());
        ASSERT_EQ(msg["width"].get<size_t>(), pcd.points.size());
        ASSERT_EQ(data.size(), step * pcd.points.size());
        for (size_t i = 0; i < pcd.points.size(); ++i) {
            const LidarPoint& p = pcd.points[i];
            const auto& f = msg["fields"];
            ASSERT_EQ(fieldValue(f, "x", data, i * step), p.x) << k << " " << i;
            ASSERT_EQ(fieldValue(f, "y", data, i * step), p.y);
            ASSERT_EQ(fieldValue(f, "z", data, i * step), p.z);
            ASSERT_EQ(fieldValue(f, "intensity", data, i * step), p.intensity);
            ASSERT_EQ(fieldValue(f, "ring", data, i * step), p.ring);
            ASSERT_EQ(fieldValue(f, "return", data, i * step), p.return_index);
            ASSERT_EQ(fieldValue(f, "source", data, i * step), p.source);
            ASSERT_EQ(fieldValue(f, "time", data, i * step), p.time_s);
            smoke += p.source == 1;
            second += p.return_index == 1;
        }
        ++k;
    }
    EXPECT_EQ(k, 3u);
    EXPECT_GT(smoke, 100u);
    EXPECT_GT(second, 100u);
}

TEST(BagCli, ReadsTheRos1BagsDebiansRosbagWrote)
{
    if (std::system("/usr/bin/python3 -c 'import rosbag, sensor_msgs.msg' >/dev/null 2>&1") != 0) {
        if (std::getenv("SMOKESCAN_REQUIRE_READERS")) FAIL() << "python3-rosbag is not installed";
        GTEST_SKIP() << "python3-rosbag and python3-sensor-msgs are missing (scripts/setup.sh installs them)";
    }
    for (const std::string compression : {"none", "bz2", "lz4"}) {
        const std::string bag = (dir() / ("ros1_" + compression + ".bag")).string();
        const std::string cmd = "/usr/bin/python3 " SMOKESCAN_SOURCE_DIR "/tests/py/write_ros1_bag.py " + bag + " " +
            compression + " 30 682 4";
        ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
        const BagLaserScans b = readBagLaserScans(bag, "");
        EXPECT_EQ(b.topic, "/front/scan");
        expectTheWritersRule(b, 30, compression);
        // Its camera frames (bgra8, padded rows): the saturation drawn into them, on their stamps.
        const SaturationSeries sat = measureBagSaturation(bag, "", frameRegions({"block=2,1,4,3"}, {}));
        ASSERT_EQ(sat.time_s.size(), 4u) << compression;
        for (size_t k = 0; k < 4; ++k) {
            EXPECT_DOUBLE_EQ(sat.time_s[k], 10 + 0.5 * double(k)) << compression;
            EXPECT_NEAR(sat.saturation[k], 0.2 * double(k), 1e-6) << compression;
        }
        EXPECT_NE(bagError(bag, "/tf").find("topic /tf is tf2_msgs/TFMessage, not sensor_msgs/LaserScan"),
                  std::string::npos)
            << bagError(bag, "/tf");
        EXPECT_NE(bagError(bag, "/rear/scan").find("has no topic /rear/scan (LaserScan topics: /front/scan)"),
                  std::string::npos);
        // Truncated, and a chunk's length past the file's end: refused before librosbag reads it.
        const std::string text = slurp(bag);
        if (compression == "none") {
            // Any one byte of the chunk's records and of the index after it changed: read, or refused in
            // one line (librosbag follows these lengths and offsets unchecked).
            int refused = 0;
            for (size_t at = 4096 + 13; at < text.size(); at += text.size() / 300) {
                std::string bad = text;
                bad[at] = char(bad[at] ^ 0x5A);
                const std::string e = bagError(writeBytes("ros1_flip.bag", {bad.begin(), bad.end()}), "/front/scan");
                EXPECT_EQ(e.find('\n'), std::string::npos) << at << ": " << e;
                refused += e != "read";
            }
            EXPECT_GT(refused, 10);
            // A scan stamped at time 0 (ROS 1's "no time", which librosbag drops): refused, not
            // read one scan short.
            const std::string zero = (dir() / "ros1_t0.bag").string();
            const std::string write0 =
                "/usr/bin/python3 " SMOKESCAN_SOURCE_DIR "/tests/py/write_ros1_bag.py " + zero + " none 3 682 0 0";
            ASSERT_EQ(std::system(write0.c_str()), 0) << write0;
            EXPECT_NE(bagError(zero, "/front/scan").find("is a message stamped at time 0"), std::string::npos)
                << bagError(zero, "/front/scan");
            // The first index record's entries ([time 8 bytes, offset 4] each) changed: an entry at
            // time 0, and an entry pointing at its neighbour's message, which leaves one message
            // that no entry points to. librosbag would read the bag one message short either way.
            size_t entries = std::string::npos;
            for (size_t pos = 13; pos + 8 <= text.size();) {  // the top-level records after the magic
                uint32_t hl, dl;
                std::memcpy(&hl, text.data() + pos, 4);
                std::memcpy(&dl, text.data() + pos + 4 + hl, 4);
                if (text.substr(pos + 4, hl).find(std::string("op=\x04", 4)) != std::string::npos) {
                    entries = pos + 8 + hl;
                    break;
                }
                pos += 8 + size_t(hl) + dl;
            }
            ASSERT_NE(entries, std::string::npos);
            std::string at0 = text;
            std::fill(at0.begin() + long(entries), at0.begin() + long(entries) + 8, '\0');
            const std::string e0 = bagError(writeBytes("ros1_index_t0.bag", {at0.begin(), at0.end()}), "/front/scan");
            EXPECT_NE(e0.find("of its chunk at time 0"), std::string::npos) << e0;
            std::string twice = text;
            std::copy(text.begin() + long(entries) + 8, text.begin() + long(entries) + 12,
                      twice.begin() + long(entries) + 20);
            const std::string e1 =
                bagError(writeBytes("ros1_unindexed.bag", {twice.begin(), twice.end()}), "/front/scan");
            EXPECT_NE(e1.find("no index entry points to (librosbag would skip it)"), std::string::npos) << e1;
        }
        const std::vector<uint8_t> cut(text.begin(), text.begin() + long(text.size() / 2));
        const std::string e = bagError(writeBytes("ros1_cut.bag", cut));
        EXPECT_NE(e.find("ros1_cut.bag"), std::string::npos) << e;
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
        // Its first line alone: named as such (librosbag's own text had no file offset).
        const std::string magic = bagError(writeBytes("ros1_magic.bag", {text.begin(), text.begin() + 13}));
        EXPECT_NE(magic.find("ros1_magic.bag: holds a ROS 1 bag's first line and nothing after it"), std::string::npos)
            << magic;
    }
}

TEST(Bag, AnLms200ScanIsALaserScanInItsOwnAnglesAndUnitsWithItsCodesAsRep117Says)
{
    for (double mode : {8.0, 80.0}) {
        const LrfSpec spec = lms200(1.0, mode);
        Scan scan;
        scan.time_s = 2.5;
        scan.value.assign(size_t(spec.n_beams), 1234);
        scan.value[1] = 8183;  // no echo
        scan.value[2] = 8189;  // weak or ambiguous
        scan.value[3] = 8191;  // dazzled
        const LaserScanMsg m = laserScanOf(scan, spec, "sick");
        const double unit = mode == 8.0 ? 0.001 : 0.01;
        EXPECT_EQ(m.angle_min, 0.0f);  // the LMS200's 0…180°, 90° ahead
        EXPECT_FLOAT_EQ(m.angle_max, float(M_PI));
        EXPECT_FLOAT_EQ(m.angle_increment, float(M_PI / 180));
        EXPECT_FLOAT_EQ(m.range_max, float(8182 * unit));
        EXPECT_EQ(m.ranges.size(), 181u);
        EXPECT_EQ(m.ranges[0], float(1234 * unit));
        EXPECT_TRUE(std::isinf(m.ranges[1]) && m.ranges[1] > 0);
        EXPECT_TRUE(std::isnan(m.ranges[2]));
        EXPECT_TRUE(std::isnan(m.ranges[3]));
        EXPECT_EQ(m.header.stamp.nanoseconds(), 2500000000ull);
        // Read back as the LMS200's log: its unit, +Inf its no-echo code, NaN an error code.
        BagLaserScans b;
        b.source = "x.bag";
        b.topic = "/scan";
        b.scans = {m};
        const RecordedLog log = recordedLogOf(b, spec);
        EXPECT_EQ(log.unit_m, unit);
        EXPECT_EQ(log.scans[0].range[0], 1234.0);
        EXPECT_EQ(log.scans[0].range[1], 8183.0);
        EXPECT_TRUE(spec.isErrorValue((long long)log.scans[0].range[2]));
        EXPECT_NEAR(log.scans[0].angle_rad[90], M_PI / 2, 1e-6);
    }
}

TEST(BagCli, ABagOfManyChunksIsReadByTheIndependentReaderThroughItsIndexes)
{
    SMOKESCAN_NEED_READERS();
    std::vector<double> t;
    for (int k = 0; k < 200; ++k) t.push_back(3 + 0.05 * k);
    const std::string mcap = writeBytes("many_chunks.mcap", scanMcap(t, 2000));
    const nlohmann::json j = readIndependently(mcap);
    EXPECT_TRUE(j["problems"].empty()) << j["problems"];
    EXPECT_GT(j["chunks"].get<int>(), 20);
    EXPECT_EQ(j["chunks"], j["chunkIndexes"]);
    EXPECT_EQ(j["messageIndexes"], j["chunks"]);  // one channel with messages in each chunk
    ASSERT_EQ(j["messages"].size(), t.size());
    for (size_t k = 0; k < t.size(); ++k) {
        const auto& m = j["messages"][k];
        EXPECT_EQ(std::stoull(m["logTime"].get<std::string>()), (unsigned long long)std::llround(t[k] * 1e9));
        EXPECT_EQ(m["sequence"], k);
        EXPECT_EQ(m["message"]["ranges"][7].get<float>(), float(t[k]));
    }
}

TEST(Bag, StampsAndBeamsAreCheckedOnEveryScan)
{
    // A stamp that is not a time, on the scan that has it.
    std::ostringstream o;
    {
        McapWriter w(o);
        const uint16_t ch =
            w.addChannel(w.addSchema(kLaserScanType.name, "ros2msg", kLaserScanType.definition), "/scan", "cdr");
        for (int k = 0; k < 3; ++k) {
            LaserScanMsg m;
            m.header.stamp = {10 + k, k == 1 ? 1999999999u : 0u};
            m.ranges.assign(682, 1.0f);
            w.write(ch, uint64_t(k), uint64_t(k), encode(m));
        }
        w.finish();
    }
    const std::string text = o.str();
    const std::string e = bagError(writeBytes("bad_stamp.mcap", {text.begin(), text.end()}));
    EXPECT_NE(e.find("message 1 on /scan"), std::string::npos) << e;
    EXPECT_NE(e.find("not a time"), std::string::npos) << e;
    // Every scan's beams are the sensor's: the first angle and the step, not just scan 0's.
    const LrfSpec urg = urg04lx();
    BagLaserScans b;
    b.source = "geometry.mcap";
    b.topic = "/scan";
    for (int k = 0; k < 3; ++k) {
        LaserScanMsg m;
        m.header.stamp = {10 + k, 0};
        m.angle_min = float(urg.angle(0));
        m.angle_increment = float(urg.dangle_rad);
        m.angle_max = float(urg.angle(urg.n_beams - 1));
        m.ranges.assign(size_t(urg.n_beams), 1.0f);
        b.scans.push_back(m);
    }
    EXPECT_EQ(recordedLogOf(b, urg).scans.size(), 3u);
    b.scans[2].angle_min = 0;
    try {
        (void)recordedLogOf(b, urg);
        ADD_FAILURE() << "scan 2's beams taken";
    } catch (const Error& x) {
        EXPECT_NE(std::string(x.what()).find("geometry.mcap: /scan scan 2"), std::string::npos) << x.what();
    }
    b.scans[2].angle_min = float(urg.angle(0));
    b.scans[1].angle_max = NAN;
    EXPECT_THROW((void)recordedLogOf(b, urg), Error);
    EXPECT_THROW((void)recordedLogOf(b, lms200()), Error);  // another sensor's beams
}

TEST(BagCli, ABagsFilesAreInputsNoOutputMayReplaceAndAFifoIsRefused)
{
    const std::string bag = (dir() / "input_bag").string(), sat = file("input_bag.csv");
    fs::remove_all(bag);
    // A trailing slash names the bag by its folder.
    ASSERT_EQ(cli("scan bocas --from 80 --to 85 --rate 2 --quiet --bag " + bag + "/ --saturation-out " + sat).status,
              0);
    const fs::path mcap = fs::path(bag) / "input_bag_0.mcap";
    ASSERT_TRUE(fs::exists(mcap));
    const std::string before = slurp(mcap), meta = slurp(fs::path(bag) / "metadata.yaml");
    const std::string common = " --saturation " + sat + " --scene bocas";
    for (const std::string& out : {mcap.string(), (fs::path(bag) / "metadata.yaml").string()}) {
        const CliRun r = cli("fit --bag " + bag + common + " --out " + out);
        EXPECT_NE(r.status, 0);
        EXPECT_NE(r.err.find("is the input of --bag"), std::string::npos) << r.err;
    }
    EXPECT_EQ(slurp(mcap), before);
    EXPECT_EQ(slurp(fs::path(bag) / "metadata.yaml"), meta);
    const fs::path fifo = dir() / "bag_fifo";
    fs::remove(fifo);
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    expectBad("fit --bag " + fifo.string() + common + " --out " + file("fifo.toml"), "is not a regular file",
              file("fifo.toml"));
    // A text input that is a FIFO no one writes reads as empty at once, not a wait.
    expectBad("fit --laser " + fifo.string() + common + " --out " + file("fifo.toml"), "holds no scans",
              file("fifo.toml"));
}
