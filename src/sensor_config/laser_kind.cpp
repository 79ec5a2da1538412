#include "smokescan/sensor_config/laser_kind.hpp"

#include <vector>

#include "kinds/kinds.hpp"
#include "smokescan/core/error.hpp"

namespace smokescan {
namespace {

/// Every kind, in SensorType's order (laserKind checks it).
const std::vector<const LaserKind*>& registry()
{
    static const std::vector<const LaserKind*> kinds = {&kinds::urg04lx(), &kinds::lms200()};
    return kinds;
}

}  // namespace

void LaserKind::readOwnKeys(TomlTable&, SensorConfig&) const {}

const LaserKind& laserKind(SensorType type)
{
    const size_t i = size_t(type);
    if (i >= registry().size() || registry()[i]->type() != type) throw Error("sensor", "unknown sensor type");
    return *registry()[i];
}

const LaserKind* findLaserKind(const std::string& name)
{
    for (size_t i = 0; i < registry().size(); ++i)
        if (name == registry()[i]->name()) return registry()[i];
    return nullptr;
}

const char* sensorTypeName(SensorType t) { return laserKind(t).name(); }

std::optional<SensorType> parseSensorType(const std::string& name)
{
    const LaserKind* k = findLaserKind(name);
    return k ? std::optional<SensorType>(k->type()) : std::nullopt;
}

const char* sensorTypeNames()
{
    static const std::string names = [] {
        std::string s;
        for (size_t i = 0; i < registry().size(); ++i)
            s += std::string(i == 0 ? "" : i + 1 == registry().size() ? " or " : ", ") + registry()[i]->name();
        return s;
    }();
    return names.c_str();
}

}  // namespace smokescan
