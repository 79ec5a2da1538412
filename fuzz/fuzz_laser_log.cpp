// Fuzzes the laser log reader (strict and lenient).
#include "fuzz_common.hpp"
#include "smokescan/io/recorded.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    return fuzzReader(data, size, [](const std::string& text) {
        smokescan::ReadOptions o;
        o.lenient = !text.empty() && (text[0] & 1);
        (void)smokescan::parseRecordedLog(text, "fuzz.log", o);
    });
}
