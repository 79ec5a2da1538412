#include "smokescan/scene/scene.hpp"

namespace smokescan {

int Scene::findSensor(const std::string& key) const
{
    for (size_t i = 0; i < sensors.size(); ++i)
        if (sensors[i].name == key) return int(i);
    for (size_t i = 0; i < sensors.size(); ++i)
        if (sensorTypeName(sensors[i].config.type) == key) return int(i);
    return -1;
}

}  // namespace smokescan
