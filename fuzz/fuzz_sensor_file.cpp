// Fuzzes the sensor file reader, applied to a URG-04LX config.
#include "fuzz_common.hpp"
#include "smokescan/sensor_config/sensor_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    return fuzzReader(data, size, [](const std::string& text) {
        smokescan::SensorConfig c = smokescan::SensorConfig::defaults(smokescan::SensorType::Urg04lx);
        smokescan::applySensorText(text, "fuzz.toml", c);
    });
}
