#include "ros1_bag.hpp"

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>

#include <cstring>
#include <fstream>
#include <map>

#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"

namespace smokescan::detail {
namespace {

constexpr char kMagic[] = "#ROSBAG V2.0\n";
constexpr size_t kMagicBytes = sizeof kMagic - 1;

/// A record's header fields (name=value, each with its own length).
std::map<std::string, std::string> headerFields(const std::string& h, const std::string& where)
{
    std::map<std::string, std::string> f;
    size_t at = 0;
    while (at < h.size()) {
        if (h.size() - at < 4) throw Error(where, "ends inside a header field's length");
        uint32_t n;
        std::memcpy(&n, h.data() + at, 4);
        at += 4;
        if (n > h.size() - at)
            throw Error(where, "has a header field of " + std::to_string(n) + " bytes past its header");
        const std::string field = h.substr(at, n);
        at += n;
        const size_t eq = field.find('=');
        if (eq == std::string::npos) throw Error(where, "has a header field without '='");
        f[field.substr(0, eq)] = field.substr(eq + 1);
    }
    return f;
}

/// Walks the file's records, checking each length and the fields librosbag trusts.
void checkStructure(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, "cannot be opened");
    in.seekg(0, std::ios::end);
    const uint64_t size = uint64_t(in.tellg());
    in.seekg(0);
    char magic[kMagicBytes];
    if (size < kMagicBytes || !in.read(magic, kMagicBytes) || std::memcmp(magic, kMagic, kMagicBytes) != 0)
        throw Error(path, "is not a ROS 1 bag (format 2.0)");
    uint64_t pos = kMagicBytes, records = 0;
    bool bag_header = false;
    while (pos < size) {
        const std::string where = path + ": record at byte " + std::to_string(pos);
        if (size - pos < 8) throw Error(where, "ends inside its lengths (truncated?)");
        uint32_t hn;
        in.seekg(std::streamoff(pos));
        in.read(reinterpret_cast<char*>(&hn), 4);
        if (hn > size - pos - 8 || hn > (1u << 20))
            throw Error(where, "claims a header of " + std::to_string(hn) + " bytes");
        std::string h(hn, '\0');
        in.read(h.data(), hn);
        uint32_t dn;
        in.read(reinterpret_cast<char*>(&dn), 4);
        if (!in) throw Error(where, "could not be read");
        if (dn > size - pos - 8 - hn)
            throw Error(where, "claims " + std::to_string(dn) + " bytes past the file's end (truncated?)");
        const auto f = headerFields(h, where);
        const auto op = f.find("op");
        if (op == f.end() || op->second.size() != 1) throw Error(where, "has no op");
        auto u32 = [&](const char* name) {
            const auto v = f.find(name);
            if (v == f.end() || v->second.size() != 4) throw Error(where, std::string("has no 4-byte ") + name);
            uint32_t x;
            std::memcpy(&x, v->second.data(), 4);
            return x;
        };
        switch (op->second[0]) {
        case 0x03: {  // the bag header
            const auto index = f.find("index_pos");
            if (index == f.end() || index->second.size() != 8) throw Error(where, "has no index_pos");
            uint64_t at;
            std::memcpy(&at, index->second.data(), 8);
            if (at > size) throw Error(where, "puts the index at byte " + std::to_string(at) + ", past the file's end");
            if (u32("conn_count") > 100000 || u32("chunk_count") > 10000000) throw Error(where, "counts too much");
            bag_header = true;
            break;
        }
        case 0x05: {  // a chunk
            const auto c = f.find("compression");
            if (c == f.end() || (c->second != "none" && c->second != "bz2" && c->second != "lz4"))
                throw Error(where, "is a chunk of an unknown compression");
            if (u32("size") > limits::kBagChunkBytes) throw Error(where, "is a chunk over the limit unpacked");
            break;
        }
        default:
            break;
        }
        if (!bag_header) throw Error(where, "should be the bag header");
        if (++records > uint64_t(limits::kBagMessages)) throw Error(path, "has too many records");
        pos += 8 + uint64_t(hn) + dn;
    }
}

}  // namespace

bool isRos1Bag(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    char magic[kMagicBytes];
    return in.read(magic, kMagicBytes) && std::memcmp(magic, kMagic, kMagicBytes) == 0;
}

BagLaserScans readRos1LaserScans(const std::string& path, const std::string& topic)
{
    checkStructure(path);
    BagLaserScans out;
    out.source = path;
    try {
        rosbag::Bag bag(path, rosbag::bagmode::Read);
        std::map<std::string, std::string> types;
        for (const rosbag::ConnectionInfo* c : rosbag::View(bag).getConnections()) types[c->topic] = c->datatype;
        std::string chosen = topic, scans;
        for (const auto& [t, type] : types)
            if (type == "sensor_msgs/LaserScan") scans += (scans.empty() ? "" : ", ") + t;
        if (chosen.empty()) {
            if (scans.empty()) throw Error(path, "has no sensor_msgs/LaserScan topic");
            if (scans.find(',') != std::string::npos)
                throw Error(path, "has several LaserScan topics (" + scans + "): give --topic");
            chosen = scans;
        }
        const auto type = types.find(chosen);
        if (type == types.end())
            throw Error(path, "has no topic " + chosen + (scans.empty() ? "" : " (LaserScan topics: " + scans + ")"));
        if (type->second != "sensor_msgs/LaserScan")
            throw Error(path, "topic " + chosen + " is " + type->second + ", not sensor_msgs/LaserScan");
        out.topic = chosen;
        for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(chosen))) {
            const auto s = m.instantiate<sensor_msgs::LaserScan>();
            if (!s) throw Error(path, "a message on " + chosen + " is not a sensor_msgs/LaserScan");
            if ((int64_t)out.scans.size() >= limits::kBagMessages)
                throw Error(path, "has too many messages on " + chosen);
            LaserScanMsg l;
            l.header.stamp.sec = int32_t(s->header.stamp.sec);
            l.header.stamp.nanosec = s->header.stamp.nsec;
            l.header.frame_id = s->header.frame_id;
            l.angle_min = s->angle_min;
            l.angle_max = s->angle_max;
            l.angle_increment = s->angle_increment;
            l.time_increment = s->time_increment;
            l.scan_time = s->scan_time;
            l.range_min = s->range_min;
            l.range_max = s->range_max;
            l.ranges = s->ranges;
            l.intensities = s->intensities;
            if (!out.scans.empty() &&
                s->header.stamp.toNSec() <=
                    uint64_t(out.scans.back().header.stamp.sec) * 1000000000ULL + out.scans.back().header.stamp.nanosec)
                throw Error(path,
                            "scan " + std::to_string(out.scans.size()) + " on " + chosen +
                                " has a stamp that does not follow the previous scan's (stamps must increase)");
            out.scans.push_back(std::move(l));
        }
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {  // librosbag's and roscpp_serialization's exceptions
        std::string m = e.what();
        for (char& c : m)
            if (c == '\n' || c == '\r') c = ' ';
        throw Error(path, "could not be read as a ROS 1 bag: " + m);
    }
    if (out.scans.empty()) throw Error(path, "has no messages on " + out.topic);
    return out;
}

}  // namespace smokescan::detail
