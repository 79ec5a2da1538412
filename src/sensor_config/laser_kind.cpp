#include "smokescan/sensor_config/laser_kind.hpp"

#include "kinds/kinds.hpp"
#include "smokescan/core/error.hpp"

namespace smokescan {
namespace {

/// Every kind, in SensorType's order.
const LaserKind* const* registry()
{
    static const LaserKind* const kinds[] = {&kinds::urg04lx(), &kinds::lms200()};
    return kinds;
}
constexpr size_t kKinds = 2;

}  // namespace

std::string LaserKind::withArticle() const
{
    const char c = name()[0];
    const bool vowel = c == 'a' || c == 'e' || c == 'i' || c == 'o' || c == 'u';
    return std::string(vowel ? "an " : "a ") + name();
}

void LaserKind::readOwnKeys(TomlTable&, SensorConfig&) const {}

const LaserKind& laserKind(SensorType type)
{
    const size_t i = size_t(type);
    if (i >= kKinds || registry()[i]->type() != type) throw Error("sensor", "unknown sensor type");
    return *registry()[i];
}

const LaserKind* findLaserKind(const std::string& name)
{
    for (size_t i = 0; i < kKinds; ++i)
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
        for (size_t i = 0; i < kKinds; ++i)
            s += std::string(i == 0 ? "" : i + 1 == kKinds ? " or " : ", ") + registry()[i]->name();
        return s;
    }();
    return names.c_str();
}

}  // namespace smokescan
