#include "smokescan/lidar/point_cloud_io.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ostream>

#include "smokescan/io/atomic_file.hpp"

namespace smokescan {
namespace {

/// One point's fields packed in the files' order, little endian (this machine's order).
void pack(std::ostream& o, const LidarPoint& p)
{
    char buf[24];
    size_t at = 0;
    auto put = [&](const auto& v) {
        std::memcpy(buf + at, &v, sizeof v);
        at += sizeof v;
    };
    put(p.x);
    put(p.y);
    put(p.z);
    put(p.intensity);
    put(p.ring);
    put(p.return_index);
    put(p.time_s);
    put(p.source);
    o.write(buf, std::streamsize(at));
}

/// A pose as "tx ty tz qw qx qy qz" (the quaternion with qw ≥ 0), separated by `sep`.
std::string poseText(const Pose& pose, char sep)
{
    Eigen::Quaterniond q(pose.R);
    q.normalize();
    if (q.w() < 0) q.coeffs() *= -1;
    // Rounding's residue of a right angle (6e-17) and −0 written as 0.
    auto clean = [](double v) { return std::abs(v) < 1e-15 ? 0.0 : v; };
    char buf[512];
    std::snprintf(buf, sizeof buf, "%.17g%c%.17g%c%.17g%c%.17g%c%.17g%c%.17g%c%.17g", clean(pose.t.x()), sep,
                  clean(pose.t.y()), sep, clean(pose.t.z()), sep, clean(q.w()), sep, clean(q.x()), sep, clean(q.y()),
                  sep, clean(q.z()));
    return buf;
}

std::string seconds(double t)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", t);  // a double exactly (epoch times too)
    return buf;
}

}  // namespace

std::string frameIndexHeader()
{
    std::string h = "frame,file,start_s,end_s";
    for (const char* when : {"start", "end"})
        for (const char* c : {"x_m", "y_m", "z_m", "qw", "qx", "qy", "qz"}) h += std::string(",") + when + "_" + c;
    return h + "\n";
}

std::string frameIndexRow(const LidarFrame& frame, const std::string& file)
{
    return std::to_string(frame.index) + "," + file + "," + seconds(frame.start_s) + "," + seconds(frame.end_s) + "," +
        poseText(frame.start_pose, ',') + "," + poseText(frame.end_pose, ',') + "\n";
}

void writePcd(const std::string& path, const LidarFrame& frame)
{
    static_assert(sizeof(float) == 4, "PCD's F 4");
    AtomicFile f(path);
    std::ostream& o = f.stream();
    const size_t n = frame.points.size();
    o << "# .PCD v0.7 - Point Cloud Data file format (smokescan lidar frame " << frame.index << ", start_s "
      << seconds(frame.start_s) << ")\n"
      << "VERSION 0.7\nFIELDS x y z intensity ring return_index time source\n"
      << "SIZE 4 4 4 4 2 1 4 1\nTYPE F F F F U U F U\nCOUNT 1 1 1 1 1 1 1 1\n"
      << "WIDTH " << n << "\nHEIGHT 1\nVIEWPOINT " << poseText(frame.start_pose, ' ') << "\nPOINTS " << n
      << "\nDATA binary\n";
    for (const LidarPoint& p : frame.points) pack(o, p);
    f.commit();
}

void writePly(const std::string& path, const LidarFrame& frame)
{
    AtomicFile f(path);
    std::ostream& o = f.stream();
    o << "ply\nformat binary_little_endian 1.0\ncomment smokescan lidar frame " << frame.index << "\n"
      << "comment start_s " << seconds(frame.start_s) << "\ncomment viewpoint " << poseText(frame.start_pose, ' ')
      << "\n"
      << "element vertex " << frame.points.size() << "\n"
      << "property float x\nproperty float y\nproperty float z\nproperty float intensity\n"
      << "property uint16 ring\nproperty uchar return_index\nproperty float time\nproperty uchar source\n"
      << "end_header\n";
    for (const LidarPoint& p : frame.points) pack(o, p);
    f.commit();
}

}  // namespace smokescan
