#include "smokescan/bag/ros_messages.hpp"

#include <cmath>

#include "smokescan/bag/cdr.hpp"
#include "smokescan/core/error.hpp"

namespace smokescan {

RosTime RosTime::fromSeconds(double t_s)
{
    if (!std::isfinite(t_s) || t_s < 0 || t_s >= 2147483647.0)
        throw Error("stamp", "a time of " + std::to_string(t_s) + " s cannot be a ROS stamp (0 … 2^31 s)");
    const long long ns = std::llround(t_s * 1e9);
    RosTime r;
    r.sec = int32_t(ns / 1000000000LL);
    r.nanosec = uint32_t(ns % 1000000000LL);
    return r;
}

namespace {

#define SMOKESCAN_SEPARATOR "================================================================================\n"
#define SMOKESCAN_HEADER_DEPS                                                                                        \
    SMOKESCAN_SEPARATOR "MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id\n" SMOKESCAN_SEPARATOR \
                        "MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n"

void putHeader(CdrWriter& w, const RosHeader& h)
{
    w.put<int32_t>(h.stamp.sec);
    w.put<uint32_t>(h.stamp.nanosec);
    w.putString(h.frame_id);
}

RosHeader getHeader(CdrReader& r)
{
    RosHeader h;
    h.stamp.sec = r.get<int32_t>();
    h.stamp.nanosec = r.get<uint32_t>();
    h.frame_id = r.getString();
    return h;
}

/// The header and the seven float32 a LaserScan and a MultiEchoLaserScan open with.
template <class Scan>
void putScanFields(CdrWriter& w, const Scan& m)
{
    putHeader(w, m.header);
    for (float v :
         {m.angle_min, m.angle_max, m.angle_increment, m.time_increment, m.scan_time, m.range_min, m.range_max})
        w.put<float>(v);
}

void finished(const CdrReader& r, const std::string& what)
{
    if (r.remaining() > 3)  // at most the padding a writer may add to a 4-byte boundary
        throw Error(what, std::to_string(r.remaining()) + " bytes left after the message (another type?)");
}

}  // namespace

const RosType kLaserScanType = {
    "sensor_msgs/msg/LaserScan",
    "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\n"
    "float32 time_increment\nfloat32 scan_time\nfloat32 range_min\nfloat32 range_max\n"
    "float32[] ranges\nfloat32[] intensities\n" SMOKESCAN_HEADER_DEPS};

const RosType kTfType = {
    "tf2_msgs/msg/TFMessage",
    "geometry_msgs/TransformStamped[] transforms\n" SMOKESCAN_SEPARATOR
    "MSG: geometry_msgs/TransformStamped\nstd_msgs/Header header\nstring child_frame_id\n"
    "geometry_msgs/Transform transform\n" SMOKESCAN_SEPARATOR
    "MSG: geometry_msgs/Transform\ngeometry_msgs/Vector3 translation\n"
    "geometry_msgs/Quaternion rotation\n" SMOKESCAN_SEPARATOR
    "MSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z\n" SMOKESCAN_SEPARATOR
    "MSG: geometry_msgs/Quaternion\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 w\n" SMOKESCAN_HEADER_DEPS};

const RosType kPointCloud2Type = {
    "sensor_msgs/msg/PointCloud2",
    "std_msgs/Header header\nuint32 height\nuint32 width\nsensor_msgs/PointField[] fields\nbool is_bigendian\n"
    "uint32 point_step\nuint32 row_step\nuint8[] data\nbool is_dense\n" SMOKESCAN_SEPARATOR
    "MSG: sensor_msgs/PointField\nuint8 INT8=1\nuint8 UINT8=2\nuint8 INT16=3\nuint8 UINT16=4\nuint8 INT32=5\n"
    "uint8 UINT32=6\nuint8 FLOAT32=7\nuint8 FLOAT64=8\nstring name\nuint32 offset\nuint8 datatype\n"
    "uint32 count\n" SMOKESCAN_HEADER_DEPS};

const RosType kImageType = {"sensor_msgs/msg/Image",
                            "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\n"
                            "uint32 step\nuint8[] data\n" SMOKESCAN_HEADER_DEPS};

const RosType kMultiEchoLaserScanType = {
    "sensor_msgs/msg/MultiEchoLaserScan",
    "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\n"
    "float32 time_increment\nfloat32 scan_time\nfloat32 range_min\nfloat32 range_max\n"
    "sensor_msgs/LaserEcho[] ranges\nsensor_msgs/LaserEcho[] intensities\n" SMOKESCAN_SEPARATOR
    "MSG: sensor_msgs/LaserEcho\nfloat32[] echoes\n" SMOKESCAN_HEADER_DEPS};
#undef SMOKESCAN_HEADER_DEPS
#undef SMOKESCAN_SEPARATOR

std::vector<uint8_t> encode(const MultiEchoLaserScanMsg& m)
{
    CdrWriter w;
    putScanFields(w, m);
    for (const auto* echoes : {&m.ranges, &m.intensities}) {
        w.put<uint32_t>(uint32_t(echoes->size()));
        for (const std::vector<float>& e : *echoes) w.putSequence(e);
    }
    return w.bytes();
}

std::vector<uint8_t> encode(const ImageMsg& m)
{
    CdrWriter w;
    putHeader(w, m.header);
    w.put<uint32_t>(m.height);
    w.put<uint32_t>(m.width);
    w.putString(m.encoding);
    w.put<uint8_t>(m.is_bigendian);
    w.put<uint32_t>(m.step);
    w.putSequence(m.data);
    return w.bytes();
}

ImageMsg decodeImage(const std::vector<uint8_t>& b, const std::string& what)
{
    CdrReader r(b.data(), b.size(), what);
    ImageMsg m;
    m.header = getHeader(r);
    m.height = r.get<uint32_t>();
    m.width = r.get<uint32_t>();
    m.encoding = r.getString();
    m.is_bigendian = r.get<uint8_t>();
    m.step = r.get<uint32_t>();
    m.data = r.getSequence<uint8_t>();
    finished(r, what);
    if (uint64_t(m.step) * m.height != m.data.size())
        throw Error(what, "has " + std::to_string(m.data.size()) + " bytes of pixels, not height × step");
    return m;
}

std::vector<uint8_t> encode(const LaserScanMsg& m)
{
    CdrWriter w;
    putScanFields(w, m);
    w.putSequence(m.ranges);
    w.putSequence(m.intensities);
    return w.bytes();
}

LaserScanMsg decodeLaserScan(const std::vector<uint8_t>& b, const std::string& what)
{
    CdrReader r(b.data(), b.size(), what);
    LaserScanMsg m;
    m.header = getHeader(r);
    for (float* v :
         {&m.angle_min, &m.angle_max, &m.angle_increment, &m.time_increment, &m.scan_time, &m.range_min, &m.range_max})
        *v = r.get<float>();
    m.ranges = r.getSequence<float>();
    m.intensities = r.getSequence<float>();
    finished(r, what);
    return m;
}

std::vector<uint8_t> encode(const TfMsg& m)
{
    CdrWriter w;
    w.put<uint32_t>(uint32_t(m.transforms.size()));
    for (const TransformStampedMsg& t : m.transforms) {
        putHeader(w, t.header);
        w.putString(t.child_frame_id);
        for (double v : t.translation) w.put<double>(v);
        for (double v : t.rotation) w.put<double>(v);
    }
    return w.bytes();
}

TfMsg decodeTf(const std::vector<uint8_t>& b, const std::string& what)
{
    CdrReader r(b.data(), b.size(), what);
    TfMsg m;
    const uint32_t n = r.getCount(8 + 5 + 5 + 56);  // header, two strings, seven doubles at least
    for (uint32_t i = 0; i < n; ++i) {
        TransformStampedMsg t;
        t.header = getHeader(r);
        t.child_frame_id = r.getString();
        for (double& v : t.translation) v = r.get<double>();
        for (double& v : t.rotation) v = r.get<double>();
        m.transforms.push_back(std::move(t));
    }
    finished(r, what);
    return m;
}

std::vector<uint8_t> encode(const PointCloud2Msg& m)
{
    CdrWriter w;
    putHeader(w, m.header);
    w.put<uint32_t>(m.height);
    w.put<uint32_t>(m.width);
    w.put<uint32_t>(uint32_t(m.fields.size()));
    for (const PointFieldMsg& f : m.fields) {
        w.putString(f.name);
        w.put<uint32_t>(f.offset);
        w.put<uint8_t>(f.datatype);
        w.put<uint32_t>(f.count);
    }
    w.putBool(m.is_bigendian);
    w.put<uint32_t>(m.point_step);
    w.put<uint32_t>(m.row_step);
    w.putSequence(m.data);
    w.putBool(m.is_dense);
    return w.bytes();
}

PointCloud2Msg decodePointCloud2(const std::vector<uint8_t>& b, const std::string& what)
{
    CdrReader r(b.data(), b.size(), what);
    PointCloud2Msg m;
    m.header = getHeader(r);
    m.height = r.get<uint32_t>();
    m.width = r.get<uint32_t>();
    const uint32_t n = r.getCount(4 + 1 + 4 + 1 + 4);
    for (uint32_t i = 0; i < n; ++i) {
        PointFieldMsg f;
        f.name = r.getString();
        f.offset = r.get<uint32_t>();
        f.datatype = r.get<uint8_t>();
        f.count = r.get<uint32_t>();
        m.fields.push_back(std::move(f));
    }
    m.is_bigendian = r.getBool();
    m.point_step = r.get<uint32_t>();
    m.row_step = r.get<uint32_t>();
    m.data = r.getSequence<uint8_t>();
    m.is_dense = r.getBool();
    finished(r, what);
    checkPointCloud2Layout(m, what);
    return m;
}

void checkPointCloud2Layout(const PointCloud2Msg& m, const std::string& what)
{
    if (uint64_t(m.point_step) * m.width > m.row_step)
        throw Error(what,
                    "has rows of " + std::to_string(m.width) + " points of " + std::to_string(m.point_step) +
                        " bytes (width × point_step) in " + std::to_string(m.row_step) + " bytes (row_step)");
    if (uint64_t(m.row_step) * m.height != m.data.size())
        throw Error(what,
                    "has " + std::to_string(m.data.size()) + " bytes of points, not height × row_step (" +
                        std::to_string(m.height) + " × " + std::to_string(m.row_step) + ")");
}

}  // namespace smokescan
