#include "smokescan/sensor_config/lrf.hpp"

#include "smokescan/sensor_config/laser_kind.hpp"
#include "smokescan/sensor_config/sensor_config.hpp"

namespace smokescan {

std::string LrfSpec::errorValueSummary() const { return laserKind(type).errorValueSummary(); }

LrfSpec specFor(const SensorConfig& c) { return laserKind(c.type).spec(c); }

}  // namespace smokescan
