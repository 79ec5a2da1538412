#include "ros1_bag.hpp"

#include "ros1_structure.hpp"

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

/// A ROS 1 LaserScan's bytes (no alignment, little-endian): the header (seq, stamp, frame_id),
/// seven float32, then ranges and intensities, each a uint32 count then float32s; every count
/// within the bytes left.
void checkLaserScanBytes(const std::vector<uint8_t>& b, const std::string& what)
{
    size_t at = 0;
    auto u32 = [&] {
        if (b.size() - at < 4) throw Error(what, "ends at byte " + std::to_string(at) + " (truncated)");
        uint32_t v;
        std::memcpy(&v, b.data() + at, 4);
        at += 4;
        return v;
    };
    auto skip = [&](uint64_t n) {
        if (n > b.size() - at)
            throw Error(what,
                        "claims " + std::to_string(n) + " bytes at byte " + std::to_string(at) + " with " +
                            std::to_string(b.size() - at) + " left");
        at += size_t(n);
    };
    skip(12);  // seq, stamp
    skip(u32());  // frame_id
    skip(7 * 4);
    skip(uint64_t(u32()) * 4);  // ranges
    skip(uint64_t(u32()) * 4);  // intensities
}

}  // namespace

BagLaserScans readRos1LaserScans(const std::string& path, const std::string& topic)
{
    checkRos1Structure(path);
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
            const std::string what = path + ": message " + std::to_string(out.scans.size()) + " on " + chosen;
            if (m.getDataType() != "sensor_msgs/LaserScan" ||
                m.getMD5Sum() != ros::message_traits::md5sum<sensor_msgs::LaserScan>())
                throw Error(what, "is not a sensor_msgs/LaserScan of this definition (its MD5 differs)");
            if (m.size() > limits::kBagChunkBytes) throw Error(what, "is over the limit");
            // Its bytes, checked before roscpp_serialization sizes its arrays from them.
            std::vector<uint8_t> raw(m.size());
            ros::serialization::OStream os(raw.data(), uint32_t(raw.size()));
            m.write(os);
            checkLaserScanBytes(raw, what);
            auto s = boost::make_shared<sensor_msgs::LaserScan>();
            ros::serialization::IStream is(raw.data(), uint32_t(raw.size()));
            ros::serialization::deserialize(is, *s);
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
            addLaserScan(out, std::move(l), what);
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
