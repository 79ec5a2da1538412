// Fuzzes the sensor file reader, applied to a URG-04LX mount.
#include "fuzz_common.hpp"
#include "smokescan/io/sensor_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    return fuzzReader(data, size, [](const std::string& text) {
        smokescan::SensorMount m;
        m.type = "urg04lx";
        smokescan::applySensorText(text, "fuzz.toml", m);
    });
}
