// Fuzzes the .vdb structure check that runs before OpenVDB reads a file (src/media/vdb_header.hpp).
#include <sstream>

#include "fuzz_common.hpp"
#include "media/vdb_header.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    return fuzzReader(data, size, [](const std::string& bytes) {
        std::istringstream in(bytes);
        (void)smokescan::detail::checkVdbHeader(in, bytes.size(), "fuzz.vdb");
    });
}
