#include "ros1_bag.hpp"

#include "ros1_structure.hpp"

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>

#include <cstring>
#include <fstream>
#include <functional>
#include <map>

#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"

namespace smokescan::detail {
namespace {

/// A walk over a ROS 1 message's bytes (no alignment, little-endian): each count read must
/// fit in the bytes left.
class ByteWalk {
public:
    ByteWalk(const std::vector<uint8_t>& b, const std::string& what) : b_(b), what_(what) {}
    uint32_t u32()
    {
        if (b_.size() - at_ < 4) throw Error(what_, "ends at byte " + std::to_string(at_) + " (truncated)");
        uint32_t v;
        std::memcpy(&v, b_.data() + at_, 4);
        at_ += 4;
        return v;
    }
    void skip(uint64_t n)
    {
        if (n > b_.size() - at_)
            throw Error(what_,
                        "claims " + std::to_string(n) + " bytes at byte " + std::to_string(at_) + " with " +
                            std::to_string(b_.size() - at_) + " left");
        at_ += size_t(n);
    }

private:
    const std::vector<uint8_t>& b_;
    const std::string& what_;
    size_t at_ = 0;
};

/// A LaserScan: the header (seq, stamp, frame_id), seven float32, then ranges and intensities,
/// each a uint32 count then float32s.
void checkLaserScanBytes(const std::vector<uint8_t>& b, const std::string& what)
{
    ByteWalk w(b, what);
    w.skip(12);  // seq, stamp
    w.skip(w.u32());  // frame_id
    w.skip(7 * 4);
    w.skip(uint64_t(w.u32()) * 4);  // ranges
    w.skip(uint64_t(w.u32()) * 4);  // intensities
}

/// An Image: the header, height, width, encoding, is_bigendian, step, then data (a uint32 count
/// and the bytes).
void checkImageBytes(const std::vector<uint8_t>& b, const std::string& what)
{
    ByteWalk w(b, what);
    w.skip(12);  // seq, stamp
    w.skip(w.u32());  // frame_id
    w.skip(8);  // height, width
    w.skip(w.u32());  // encoding
    w.skip(5);  // is_bigendian, step
    w.skip(w.u32());  // data
}

/// A PointCloud2: the header, height, width, the fields (a uint32 count, each a name, offset,
/// datatype and count), is_bigendian, point_step, row_step, data (a uint32 count and the bytes),
/// is_dense.
void checkPointCloud2Bytes(const std::vector<uint8_t>& b, const std::string& what)
{
    ByteWalk w(b, what);
    w.skip(12);  // seq, stamp
    w.skip(w.u32());  // frame_id
    w.skip(8);  // height, width
    for (uint32_t n = w.u32(), i = 0; i < n; ++i) {  // each field takes 13 bytes at least: n is bounded by them
        w.skip(w.u32());  // name
        w.skip(9);  // offset, datatype, count
    }
    w.skip(9);  // is_bigendian, point_step, row_step
    w.skip(w.u32());  // data
    w.skip(1);  // is_dense
}

/// A ROS 1 header as ROS 2's (no sequence number).
RosHeader headerOf(const std_msgs::Header& h)
{
    RosHeader r;
    r.stamp.sec = int32_t(h.stamp.sec);
    r.stamp.nanosec = h.stamp.nsec;
    r.frame_id = h.frame_id;
    return r;
}

/// The messages on `topic` ("" = the only one of `type`) of a ROS 1 bag, each as its bytes checked
/// by `check` before librosbag's deserialiser sizes arrays from them.
template <class Msg>
void readRos1Topic(const std::string& path, const std::string& topic, const std::string& type, const char* option,
                   void (*check)(const std::vector<uint8_t>&, const std::string&),
                   const std::function<void(Msg&&, const std::string& what)>& each, std::string& chosen)
{
    checkRos1Structure(path);
    const std::string kind = type.substr(type.find('/') + 1);
    int64_t n = 0;
    try {
        rosbag::Bag bag(path, rosbag::bagmode::Read);
        std::map<std::string, std::string> types;
        for (const rosbag::ConnectionInfo* c : rosbag::View(bag).getConnections()) types[c->topic] = c->datatype;
        std::string listed;
        chosen = topic;
        for (const auto& [t, ty] : types)
            if (ty == type) listed += (listed.empty() ? "" : ", ") + t;
        if (chosen.empty()) {
            if (listed.empty()) throw Error(path, "has no " + type + " topic");
            if (listed.find(',') != std::string::npos)
                throw Error(path, "has several " + kind + " topics (" + listed + "): give " + option);
            chosen = listed;
        }
        const auto found = types.find(chosen);
        if (found == types.end())
            throw Error(path,
                        "has no topic " + chosen + (listed.empty() ? "" : " (" + kind + " topics: " + listed + ")"));
        if (found->second != type) throw Error(path, "topic " + chosen + " is " + found->second + ", not " + type);
        for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(chosen))) {
            const std::string what = path + ": message " + std::to_string(n) + " on " + chosen;
            if (m.getDataType() != type || m.getMD5Sum() != ros::message_traits::md5sum<Msg>())
                throw Error(what, "is not a " + type + " of this definition (its MD5 differs)");
            if (m.size() > limits::kBagChunkBytes) throw Error(what, "is over the limit");
            if (++n > limits::kBagMessages) throw Error(path, "has too many messages on " + chosen);
            std::vector<uint8_t> raw(m.size());
            ros::serialization::OStream os(raw.data(), uint32_t(raw.size()));
            m.write(os);
            check(raw, what);
            Msg msg;
            ros::serialization::IStream is(raw.data(), uint32_t(raw.size()));
            ros::serialization::deserialize(is, msg);
            try {  // the caller's own failures are not the bag's
                each(std::move(msg), what);
            } catch (const Error&) {
                throw;
            } catch (const std::exception& e) {
                throw Error(what, e.what());
            }
        }
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {  // librosbag's and roscpp_serialization's exceptions
        std::string m = e.what();
        for (char& c : m)
            if (c == '\n' || c == '\r') c = ' ';
        throw Error(path, "could not be read as a ROS 1 bag: " + m);
    }
    if (n == 0) throw Error(path, "has no messages on " + chosen);
}

}  // namespace

BagLaserScans readRos1LaserScans(const std::string& path, const std::string& topic)
{
    BagLaserScans out;
    out.source = path;
    readRos1Topic<sensor_msgs::LaserScan>(
        path, topic, "sensor_msgs/LaserScan", "--topic", checkLaserScanBytes,
        [&](sensor_msgs::LaserScan&& s, const std::string& what) {
            LaserScanMsg l;
            l.header = headerOf(s.header);
            l.angle_min = s.angle_min;
            l.angle_max = s.angle_max;
            l.angle_increment = s.angle_increment;
            l.time_increment = s.time_increment;
            l.scan_time = s.scan_time;
            l.range_min = s.range_min;
            l.range_max = s.range_max;
            l.ranges = std::move(s.ranges);
            l.intensities = std::move(s.intensities);
            addLaserScan(out, std::move(l), what);
        },
        out.topic);
    return out;
}

std::string readRos1Images(const std::string& path, const std::string& topic,
                           const std::function<void(ImageMsg&&, const std::string& what)>& each)
{
    std::string chosen;
    readRos1Topic<sensor_msgs::Image>(
        path, topic, "sensor_msgs/Image", "its topic", checkImageBytes,
        [&](sensor_msgs::Image&& s, const std::string& what) {
            ImageMsg m;
            m.header = headerOf(s.header);
            m.height = s.height;
            m.width = s.width;
            m.encoding = s.encoding;
            m.is_bigendian = s.is_bigendian;
            m.step = s.step;
            m.data = std::move(s.data);
            if (uint64_t(m.step) * m.height != m.data.size())
                throw Error(what, "has " + std::to_string(m.data.size()) + " bytes of pixels, not height × step");
            each(std::move(m), what);
        },
        chosen);
    return chosen;
}

std::string readRos1PointClouds(const std::string& path, const std::string& topic,
                                const std::function<void(PointCloud2Msg&&, const std::string& what)>& each)
{
    std::string chosen;
    readRos1Topic<sensor_msgs::PointCloud2>(
        path, topic, "sensor_msgs/PointCloud2", "--topic", checkPointCloud2Bytes,
        [&](sensor_msgs::PointCloud2&& s, const std::string& what) {
            PointCloud2Msg m;
            m.header = headerOf(s.header);
            // A frame's time is its header's stamp: 0 is ROS 1's "no time" (a stamp never set).
            if (s.header.stamp.isZero())
                throw Error(what, "has the header stamp 0 (ROS 1's 'no time': the frame's time is not known)");
            m.height = s.height;
            m.width = s.width;
            for (const sensor_msgs::PointField& f : s.fields)
                m.fields.push_back({f.name, f.offset, f.datatype, f.count});
            m.is_bigendian = s.is_bigendian;
            m.point_step = s.point_step;
            m.row_step = s.row_step;
            m.data = std::move(s.data);
            m.is_dense = s.is_dense;
            checkPointCloud2Layout(m, what);
            each(std::move(m), what);
        },
        chosen);
    return chosen;
}

}  // namespace smokescan::detail
