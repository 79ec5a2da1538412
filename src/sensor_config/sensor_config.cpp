#include "smokescan/sensor_config/sensor_config.hpp"

namespace smokescan {

SensorConfig SensorConfig::defaults(SensorType type)
{
    SensorConfig c;
    c.type = type;
    c.physical = physicalDefaults(type);
    return c;
}

}  // namespace smokescan
