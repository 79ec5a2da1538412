// Fuzzes the lidar preset reader (a pattern file it names is looked for beside a folder that does
// not exist), then the frame's beam pattern of what it accepts.
#include "fuzz_common.hpp"
#include "smokescan/lidar/lidar_spec.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    return fuzzReader(data, size, [](const std::string& text) {
        const smokescan::LidarSpec s = smokescan::parseLidarSpec(text, "fuzz-nowhere/fuzz.toml");
        if ((long long)s.columns * s.channels() <= 200'000) (void)smokescan::framePattern(s);
    });
}
