// Fuzzes the point-cloud reader (PCD ascii and binary, PLY ascii and binary little endian).
#include "fuzz_common.hpp"
#include "smokescan/lidar/point_cloud_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    return fuzzReader(data, size, [](const std::string& bytes) {
        const smokescan::PointCloudFile f = smokescan::parsePointCloud(bytes, "fuzz.pcd");
        for (const smokescan::LidarPoint& p : f.points)
            if (!(p.range_m >= 0)) __builtin_trap();  // a point kept has a finite x, y, z
    });
}
