#include "smokescan/sensor_config/sensor_kind.hpp"

namespace smokescan {

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

std::optional<SensorModel> parseSensorModel(const std::string& name)
{
    for (SensorModel m : {SensorModel::Paper, SensorModel::Physical})
        if (name == sensorModelName(m)) return m;
    return std::nullopt;
}

const char* sensorModelNames() { return "paper or physical"; }

}  // namespace smokescan
