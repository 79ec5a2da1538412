#pragma once
// Internal: each laser kind's one instance (src/sensor_config/kinds/NAME.cpp), for the registry
// in laser_kind.cpp. A new kind is a file here, a line there and an entry in SensorType.
#include "smokescan/sensor_config/laser_kind.hpp"

namespace smokescan::kinds {

const LaserKind& urg04lx();
const LaserKind& lms200();

}  // namespace smokescan::kinds
