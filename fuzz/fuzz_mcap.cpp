// Fuzzes the MCAP reader (bag/mcap_reader.hpp) and, on each message it yields, the CDR decoders of
// the ROS messages smokescan reads (bag/ros_messages.hpp).
#include "fuzz_common.hpp"
#include "smokescan/bag/bag_input.hpp"
#include "smokescan/bag/mcap_reader.hpp"
#include "smokescan/bag/ros_messages.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    return fuzzReader(data, size, [](const std::string& bytes) {
        const std::vector<uint8_t> b(bytes.begin(), bytes.end());
        (void)smokescan::readMcapBytes(b, "fuzz.mcap", [](const smokescan::McapChannel&, smokescan::McapMessage&& m) {
            for (int type = 0; type < 4; ++type) try {
                    if (type == 0) (void)smokescan::decodeLaserScan(m.data, "message");
                    if (type == 1) (void)smokescan::decodeTf(m.data, "message");
                    if (type == 2) (void)smokescan::decodePointCloud2(m.data, "message");
                    if (type == 3) (void)smokescan::imageOf(smokescan::decodeImage(m.data, "message"), "message");
                } catch (const smokescan::Error& e) {
                    if (std::string(e.what()).find('\n') != std::string::npos) __builtin_trap();
                }
        });
    });
}
