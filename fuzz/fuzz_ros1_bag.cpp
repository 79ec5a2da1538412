// Fuzzes the ROS 1 bag reader (bag/bag_input.hpp: the structure check, then librosbag_storage),
// its LaserScans, its Images and its PointCloud2s:
// the bytes go to a file, which is what librosbag reads.
#include <unistd.h>

#include <cstdio>
#include <fstream>

#include "fuzz_common.hpp"
#include "smokescan/bag/bag_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    static const std::string path = "/tmp/smokescan_fuzz_ros1_" + std::to_string(::getpid()) + ".bag";
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(data), std::streamsize(size));
    const int r = fuzzReader(data, size, [](const std::string&) {
        const smokescan::BagLaserScans b = smokescan::readBagLaserScans(path, "");
        for (const smokescan::LaserScanMsg& s : b.scans)
            if (s.ranges.size() > size_t(1) << 28) __builtin_trap();
    });
    (void)fuzzReader(data, size, [](const std::string&) {
        (void)smokescan::readBagImages(
            path, "", [](smokescan::ImageMsg&& m, const std::string& what) { (void)smokescan::imageOf(m, what); });
    });
    (void)fuzzReader(data, size, [](const std::string&) {
        (void)smokescan::readBagPointClouds(path, "",
                                            [](const smokescan::PointCloud2Msg& m, double, const std::string& what) {
                                                (void)smokescan::pointCloudFileOf(m, what);
                                            });
    });
    std::remove(path.c_str());
    return r;
}
