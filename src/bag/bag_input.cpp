#include "smokescan/bag/bag_input.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>

#include "ros1_bag.hpp"
#include "smokescan/bag/mcap_reader.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/io/text_input.hpp"
#include "smokescan/lidar/lidar_spec.hpp"
#include "smokescan/sensor_config/laser_kind.hpp"

namespace smokescan {
namespace fs = std::filesystem;
namespace {

/// A file a bag is read from: it exists and is a regular file (a FIFO would block, a device
/// never ends).
void needRegular(const fs::path& p, const std::string& what)
{
    std::error_code e;
    if (!fs::exists(p, e)) throw Error(p.string(), "does not exist" + what);
    if (!fs::is_regular_file(p, e)) throw Error(p.string(), "is not a regular file" + what);
}

/// The MCAP files of a bag: a folder's, from its metadata.yaml, or the file itself.
std::vector<std::string> bagFiles(const std::string& path)
{
    if (!fs::is_directory(path)) {
        needRegular(path, "");
        return {path};
    }
    const fs::path meta = fs::path(path) / "metadata.yaml";
    if (!fs::exists(meta)) throw Error(path, "is a folder without metadata.yaml (not a rosbag2 bag)");
    needRegular(meta, "");
    const std::string text = readTextInput(meta.string(), "bag metadata", limits::kTomlInputBytes);
    YAML::Node info;
    try {
        info = YAML::Load(text)["rosbag2_bagfile_information"];
    } catch (const YAML::Exception& e) {
        throw Error(meta.string() + ":" + std::to_string(e.mark.line + 1), "is not YAML: " + e.msg);
    }
    if (!info || !info.IsMap()) throw Error(meta.string(), "has no rosbag2_bagfile_information");
    std::vector<std::string> files;
    try {
        const std::string storage = info["storage_identifier"] ? info["storage_identifier"].as<std::string>() : "";
        if (storage != "mcap")
            throw Error(
                meta.string(),
                "storage_identifier: '" + storage + "' — smokescan reads MCAP bags (convert with `ros2 bag convert`)");
        const std::string compression = info["compression_format"] ? info["compression_format"].as<std::string>() : "";
        if (!compression.empty())
            throw Error(meta.string(),
                        "compression_format: '" + compression +
                            "' (whole-file compression; MCAP's own chunk compression is read)");
        const YAML::Node paths = info["relative_file_paths"];
        if (!paths || !paths.IsSequence() || paths.size() == 0)
            throw Error(meta.string(), "relative_file_paths: no files listed");
        if (paths.size() > 10000) throw Error(meta.string(), "relative_file_paths: more than 10000 files");
        for (const YAML::Node& p : paths) {
            const fs::path f = p.as<std::string>();
            if (f.is_absolute() || f.lexically_normal().string().rfind("..", 0) == 0)
                throw Error(meta.string(), "relative_file_paths: '" + f.string() + "' is not inside the bag");
            const fs::path file = fs::path(path) / f;
            needRegular(file, " (listed in " + meta.string() + ")");
            // Inside the folder once links are followed, and listed once.
            const fs::path folder = fs::weakly_canonical(path), real = fs::weakly_canonical(file);
            const fs::path inside = real.lexically_relative(folder);
            if (inside.empty() || *inside.begin() == "..")
                throw Error(meta.string(), "relative_file_paths: '" + f.string() + "' leads outside the bag");
            if (std::find(files.begin(), files.end(), file.string()) != files.end())
                throw Error(meta.string(), "relative_file_paths: '" + f.string() + "' is listed twice");
            files.push_back(file.string());
        }
    } catch (const YAML::Exception& e) {
        throw Error(meta.string() + ":" + std::to_string(e.mark.line + 1), e.msg);
    }
    return files;
}

}  // namespace

namespace detail {

/// A scan appended after the checks every source's scans pass: a stamp that is a time (sec ≥ 0,
/// nanosec < 1e9) after the previous scan's, and the run's beams within limits::kBagBeams.
void addLaserScan(BagLaserScans& out, LaserScanMsg&& s, const std::string& what)
{
    const RosTime& t = s.header.stamp;
    if (t.sec < 0 || t.nanosec >= 1000000000u)
        throw Error(what,
                    "has the stamp " + std::to_string(t.sec) + " s " + std::to_string(t.nanosec) +
                        " ns, which is not a time (sec ≥ 0, nanosec < 1e9)");
    if (!out.scans.empty() && t.nanoseconds() <= out.scans.back().header.stamp.nanoseconds())
        throw Error(what, "has a stamp that does not follow the previous scan's (stamps must increase)");
    out.beams += s.ranges.size();
    if (out.beams > uint64_t(limits::kBagBeams))
        throw Error(what, "takes the run past " + std::to_string(limits::kBagBeams) + " beams in all");
    out.scans.push_back(std::move(s));
}

}  // namespace detail

std::vector<std::string> bagInputFiles(const std::string& path)
{
    if (!fs::is_directory(path)) return bagFiles(path);
    std::vector<std::string> files = bagFiles(path);
    files.insert(files.begin(), (fs::path(path) / "metadata.yaml").string());
    return files;
}

namespace {

/// The messages of one topic of a bag's MCAP files, in the bag's order: `topic`, or when empty the
/// bag's only topic of `type` (`kind` names such topics in errors). @return the topic read.
std::string readTopic(const std::string& path, const std::string& topic, const RosType& type, const std::string& kind,
                      const std::function<void(McapMessage&&, const std::string& what)>& each)
{
    std::map<std::string, std::string> types;  ///< every topic's type, for messages
    std::string chosen = topic;
    int64_t n = 0;
    // When the topic is the bag's only one of its type, a bad message waits until the whole bag
    // has shown there is no other: "give its topic" is the error then.
    std::optional<Error> failed;
    for (const std::string& file : bagFiles(path)) {
        const auto channels = readMcap(file, [&](const McapChannel& ch, McapMessage&& m) {
            types[ch.topic] = ch.schema_name;
            if (chosen.empty() && ch.schema_name == type.name) chosen = ch.topic;
            if (ch.topic != chosen) return;
            if (ch.schema_name != type.name)
                throw Error(file, "topic " + ch.topic + " is " + ch.schema_name + ", not " + type.name);
            if (ch.message_encoding != "cdr")
                throw Error(file, "topic " + ch.topic + " is encoded as '" + ch.message_encoding + "', not cdr");
            if (++n > limits::kBagMessages)
                throw Error(file, "has more than " + std::to_string(limits::kBagMessages) + " messages on " + ch.topic);
            if (failed) return;
            try {
                each(std::move(m), file + ": message " + std::to_string(m.sequence) + " on " + ch.topic);
            } catch (const Error& e) {
                if (!topic.empty()) throw;
                failed = e;
            }
        });
        for (const auto& [id, ch] : channels) types.emplace(ch.topic, ch.schema_name);
    }
    std::string listed;  ///< the topics of the type
    for (const auto& [t, ty] : types)
        if (ty == type.name) listed += (listed.empty() ? "" : ", ") + t;
    if (chosen.empty() && listed.find(',') == std::string::npos) chosen = listed;  // the only one, without messages
    if (n == 0) {
        if (!chosen.empty() && types.count(chosen) && types[chosen] != type.name)
            throw Error(path, "topic " + chosen + " is " + types[chosen] + ", not " + type.name);
        if (!chosen.empty() && types.count(chosen)) throw Error(path, "has no messages on " + chosen);
        throw Error(
            path,
            (chosen.empty() ? "has no " + kind + " topic" : "has no topic " + chosen) +
                (listed.empty() ? " (no " + kind + " topics at all)" : " (" + kind + " topics: " + listed + ")"));
    }
    // The only topic of the type, when none was named.
    if (topic.empty()) {
        std::string others;
        for (const auto& [t, ty] : types)
            if (ty == type.name && t != chosen) others += " " + t;
        if (!others.empty())
            throw Error(path, "has several " + kind + " topics (" + chosen + others + "): give its topic");
    }
    if (failed) throw *failed;
    return chosen;
}

/// Whether `path` is a ROS 1 bag file (read by librosbag; the others are MCAP).
bool isRos1BagFile(const std::string& path)
{
    return !fs::is_directory(path) && fs::exists(path) && detail::isRos1Bag(path);
}

/// A topic's frames' stamps: each a time (sec ≥ 0, nanosec < 1e9) after the previous frame's.
class FrameStamps {
public:
    void check(const RosTime& t, const std::string& what)
    {
        if (t.sec < 0 || t.nanosec >= 1000000000u)
            throw Error(what,
                        "has the stamp " + std::to_string(t.sec) + " s " + std::to_string(t.nanosec) +
                            " ns, which is not a time (sec ≥ 0, nanosec < 1e9)");
        if (!first_ && t.nanoseconds() <= last_.nanoseconds())
            throw Error(what, "has a stamp that does not follow the previous frame's (stamps must increase)");
        first_ = false;
        last_ = t;
    }

private:
    RosTime last_;
    bool first_ = true;
};

}  // namespace

BagLaserScans readBagLaserScans(const std::string& path, const std::string& topic)
{
    if (isRos1BagFile(path)) return detail::readRos1LaserScans(path, topic);
    BagLaserScans out;
    out.source = path;
    out.topic = readTopic(path, topic, kLaserScanType, "LaserScan", [&](McapMessage&& m, const std::string& what) {
        detail::addLaserScan(out, decodeLaserScan(m.data, what), what);
    });
    return out;
}

std::string readBagImages(const std::string& path, const std::string& topic,
                          const std::function<void(ImageMsg&&, const std::string& what)>& each)
{
    // Stamps that are times and increase, then the caller's.
    FrameStamps stamps;
    const auto checked = [&](ImageMsg&& img, const std::string& what) {
        stamps.check(img.header.stamp, what);
        each(std::move(img), what);
    };
    if (isRos1BagFile(path)) return detail::readRos1Images(path, topic, checked);
    return readTopic(path, topic, kImageType, "Image",
                     [&](McapMessage&& m, const std::string& what) { checked(decodeImage(m.data, what), what); });
}

PointCloudFile pointCloudFileOf(const PointCloud2Msg& m, const std::string& what)
{
    if (m.is_bigendian) throw Error(what, "is big-endian (smokescan reads little-endian point clouds)");
    static const std::pair<char, int> kTypes[] = {{'I', 1}, {'U', 1}, {'I', 2}, {'U', 2},
                                                  {'I', 4}, {'U', 4}, {'F', 4}, {'F', 8}};
    std::vector<PointRecordField> fields;
    for (const PointFieldMsg& f : m.fields) {
        if (f.datatype < 1 || f.datatype > 8)
            throw Error(what, "field '" + f.name + "' has datatype " + std::to_string(f.datatype) + " (1 to 8)");
        const auto [type, size] = kTypes[f.datatype - 1];
        fields.push_back({f.name, type, size, int(std::min<uint32_t>(f.count, 1u << 20)), size_t(f.offset)});
    }
    const uint64_t n = uint64_t(m.width) * uint64_t(m.height);
    if (n == 0) return PointCloudFile{};  // a bare message of no point: its fields need not be any
    if (n > uint64_t(2 * lidar_limits::kBeamsPerFrame))
        throw Error(what,
                    std::to_string(m.width) + " × " + std::to_string(m.height) + " points (at most " +
                        std::to_string(2 * lidar_limits::kBeamsPerFrame) + " a frame)");
    const uint64_t row = uint64_t(m.point_step) * m.width;
    if (m.height > 0 && (m.row_step < row || uint64_t(m.row_step) * m.height > m.data.size()))
        throw Error(what,
                    fmt("has rows of %u bytes (row_step) for %u points of %u bytes, and %zu bytes for %u rows",
                        m.row_step, m.width, m.point_step, m.data.size(), m.height));
    // The points one after another: rows padded past their points (row_step) are closed up. Rows
    // of no bytes (no points, or points of none) are not walked: 2^32 of them took the fuzzer 14 s.
    std::string bytes;
    bytes.reserve(size_t(row * m.height));
    for (uint32_t r = 0; row > 0 && r < m.height; ++r)
        bytes.append(reinterpret_cast<const char*>(m.data.data()) + size_t(r) * m.row_step, size_t(row));
    return readPointRecords(bytes, (long long)n, m.point_step, fields, what);
}

std::string readBagPointClouds(const std::string& path, const std::string& topic,
                               const std::function<void(const PointCloud2Msg&, double, const std::string&)>& each)
{
    FrameStamps stamps;
    const auto checked = [&](const PointCloud2Msg& m, const std::string& what) {
        const RosTime& t = m.header.stamp;
        stamps.check(t, what);
        each(m, double(t.sec) + 1e-9 * double(t.nanosec), what);
    };
    if (isRos1BagFile(path))
        return detail::readRos1PointClouds(path, topic,
                                           [&](PointCloud2Msg&& m, const std::string& what) { checked(m, what); });
    return readTopic(path, topic, kPointCloud2Type, "PointCloud2", [&](McapMessage&& msg, const std::string& what) {
        checked(decodePointCloud2(msg.data, what), what);
    });
}

RecordedLog recordedLogOf(const BagLaserScans& bag, const LrfSpec& spec)
{
    RecordedLog log;
    log.path = bag.source;
    log.unit_m = spec.unit_m;
    const LaserKind& kind = laserKind(spec.type);
    const size_t beams = bag.scans.front().ranges.size();
    for (size_t k = 0; k < bag.scans.size(); ++k) {
        const LaserScanMsg& s = bag.scans[k];
        if (s.ranges.size() != beams)
            throw Error(bag.source,
                        bag.topic + " scan " + std::to_string(k) + " has " + std::to_string(s.ranges.size()) +
                            " beams, the first " + std::to_string(beams));
        const std::string where = bag.source + ": " + bag.topic + " scan " + std::to_string(k);
        if (!std::isfinite(s.angle_min) || !std::isfinite(s.angle_increment) || !std::isfinite(s.angle_max))
            throw Error(where, "has angles that are not finite");
        // The sensor's beams: its first angle and its step, within a hundredth of a step.
        const double tol = 0.01 * spec.dangle_rad;
        if (std::abs(double(s.angle_min) - spec.angle(0)) > tol ||
            std::abs(double(s.angle_increment) - spec.dangle_rad) > tol)
            throw Error(where,
                        fmt("has beams from %.5f rad every %.6f rad; the %s's are from %.5f every %.6f "
                            "(a scan of another sensor? give --sensor or --sensor-type)",
                            s.angle_min, s.angle_increment, sensorTypeName(spec.type), spec.angle(0), spec.dangle_rad));
        LaserLogScan l;
        l.time_s = double(s.header.stamp.sec) + 1e-9 * double(s.header.stamp.nanosec);
        for (size_t i = 0; i < beams; ++i) {
            l.angle_rad.push_back(double(s.angle_min) + double(i) * double(s.angle_increment));
            const float r = s.ranges[i];
            if (!std::isfinite(r)) {
                l.range.push_back(double(kind.codeOfRep117(r)));
                continue;
            }
            if (r < 0 || r > 1000)
                throw Error(bag.source,
                            bag.topic + " scan " + std::to_string(k) + " beam " + std::to_string(i) + ": a range of " +
                                std::to_string(r) + " m");
            l.range.push_back(double(std::llround(double(r) / spec.unit_m)));
        }
        log.scans.push_back(std::move(l));
    }
    return log;
}

}  // namespace smokescan

namespace smokescan {

Image imageOf(const ImageMsg& m, const std::string& what)
{
    struct Layout {
        const char* encoding;
        int bytes, r, g, b;  ///< bytes a pixel; each colour's byte
    };
    static constexpr Layout kLayouts[] = {
        {"rgb8", 3, 0, 1, 2}, {"bgr8", 3, 2, 1, 0}, {"rgba8", 4, 0, 1, 2}, {"bgra8", 4, 2, 1, 0}};
    const Layout* l = nullptr;
    for (const Layout& k : kLayouts)
        if (m.encoding == k.encoding) l = &k;
    if (!l)
        throw Error(what, "is encoded '" + m.encoding + "': the saturation needs colour (rgb8, bgr8, rgba8, bgra8)");
    if (m.width == 0 || m.height == 0 || int64_t(m.width) * m.height > limits::kFramePixels)
        throw Error(what,
                    "is " + std::to_string(m.width) + "×" + std::to_string(m.height) + " pixels (at most " +
                        std::to_string(limits::kFramePixels) + ")");
    if (uint64_t(m.step) < uint64_t(m.width) * uint64_t(l->bytes) ||
        uint64_t(m.step) * m.height != uint64_t(m.data.size()))
        throw Error(what,
                    "has a row step of " + std::to_string(m.step) + " bytes for " + std::to_string(m.width) +
                        " pixels of " + std::to_string(l->bytes) + " bytes");
    Image img(int(m.width), int(m.height), 3);
    for (uint32_t y = 0; y < m.height; ++y)
        for (uint32_t x = 0; x < m.width; ++x) {
            const uint8_t* p = m.data.data() + size_t(y) * m.step + size_t(x) * size_t(l->bytes);
            img.at(int(x), int(y), 0) = float(p[l->r]) / 255.0f;
            img.at(int(x), int(y), 1) = float(p[l->g]) / 255.0f;
            img.at(int(x), int(y), 2) = float(p[l->b]) / 255.0f;
        }
    return img;
}

bool isBagPath(const std::string& path)
{
    std::error_code e;
    if (fs::is_directory(path, e)) return true;
    if (!fs::is_regular_file(path, e)) return false;
    if (detail::isRos1Bag(path)) return true;
    std::ifstream in(path, std::ios::binary);
    char head[8] = {};
    in.read(head, 8);
    return in.gcount() == 8 && std::memcmp(head, "\x89MCAP0\r\n", 8) == 0;
}

}  // namespace smokescan
