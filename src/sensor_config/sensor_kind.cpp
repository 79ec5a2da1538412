#include "smokescan/sensor_config/sensor_kind.hpp"

namespace smokescan {

const char* sensorTypeName(SensorType t)
{
    switch (t) {
    case SensorType::Urg04lx:
        return "urg04lx";
    case SensorType::Lms200:
        return "lms200";
    }
    return "?";
}

const char* sensorModelName(SensorModel m)
{
    switch (m) {
    case SensorModel::Paper:
        return "paper";
    case SensorModel::Physical:
        return "physical";
    }
    return "?";
}

std::optional<SensorType> parseSensorType(const std::string& name)
{
    for (SensorType t : {SensorType::Urg04lx, SensorType::Lms200})
        if (name == sensorTypeName(t)) return t;
    return std::nullopt;
}

std::optional<SensorModel> parseSensorModel(const std::string& name)
{
    for (SensorModel m : {SensorModel::Paper, SensorModel::Physical})
        if (name == sensorModelName(m)) return m;
    return std::nullopt;
}

const char* sensorTypeNames() { return "urg04lx or lms200"; }
const char* sensorModelNames() { return "paper or physical"; }

}  // namespace smokescan
