// Fuzzes the CDR decoders of the ROS messages smokescan reads (bag/ros_messages.hpp), and a
// PointCloud2's points (bag/bag_input.hpp); the first byte picks the message type.
#include "fuzz_common.hpp"
#include "smokescan/bag/bag_input.hpp"
#include "smokescan/bag/ros_messages.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    if (size == 0) return 0;
    return fuzzReader(data + 1, size - 1, [type = data[0] % 3](const std::string& bytes) {
        const std::vector<uint8_t> b(bytes.begin(), bytes.end());
        if (type == 0) {
            const smokescan::LaserScanMsg m = smokescan::decodeLaserScan(b, "message");
            if (m.ranges.size() * 4 > b.size()) __builtin_trap();  // never more values than bytes
        } else if (type == 1) {
            (void)smokescan::decodeTf(b, "message");
        } else {
            const smokescan::PointCloud2Msg m = smokescan::decodePointCloud2(b, "message");
            if (m.data.size() > b.size()) __builtin_trap();
            // Its points, as fit and diagnose --points read a bag's: never more than it holds.
            const smokescan::PointCloudFile pc = smokescan::pointCloudFileOf(m, "message");
            if (pc.points.size() + pc.skipped > uint64_t(m.width) * m.height) __builtin_trap();
        }
    });
}
