#include "smokescan/lidar/point_cloud_io.hpp"

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

}  // namespace

void writePcd(const std::string& path, const LidarFrame& frame)
{
    static_assert(sizeof(float) == 4, "PCD's F 4");
    AtomicFile f(path);
    std::ostream& o = f.stream();
    const size_t n = frame.points.size();
    o << "# .PCD v0.7 - Point Cloud Data file format (smokescan lidar frame " << frame.index << ")\n"
      << "VERSION 0.7\nFIELDS x y z intensity ring return_index time source\n"
      << "SIZE 4 4 4 4 2 1 4 1\nTYPE F F F F U U F U\nCOUNT 1 1 1 1 1 1 1 1\n"
      << "WIDTH " << n << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << n << "\nDATA binary\n";
    for (const LidarPoint& p : frame.points) pack(o, p);
    f.commit();
}

void writePly(const std::string& path, const LidarFrame& frame)
{
    AtomicFile f(path);
    std::ostream& o = f.stream();
    o << "ply\nformat binary_little_endian 1.0\ncomment smokescan lidar frame " << frame.index << "\n"
      << "element vertex " << frame.points.size() << "\n"
      << "property float x\nproperty float y\nproperty float z\nproperty float intensity\n"
      << "property uint16 ring\nproperty uchar return_index\nproperty float time\nproperty uchar source\n"
      << "end_header\n";
    for (const LidarPoint& p : frame.points) pack(o, p);
    f.commit();
}

}  // namespace smokescan
