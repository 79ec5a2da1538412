#include "smokescan/scene/scene.hpp"

namespace smokescan {

std::optional<LightKind> parseLightKind(const std::string& name)
{
    static const std::pair<const char*, LightKind> kNames[] = {{"area", LightKind::Area},
                                                               {"point", LightKind::Point},
                                                               {"spot", LightKind::Spot},
                                                               {"directional", LightKind::Directional},
                                                               {"ambient", LightKind::Ambient}};
    for (const auto& [n, k] : kNames)
        if (name == n) return k;
    return std::nullopt;
}

std::optional<CameraKind> parseCameraKind(const std::string& name)
{
    if (name == "pinhole") return CameraKind::Pinhole;
    if (name == "omni") return CameraKind::Omni;
    return std::nullopt;
}

namespace {
Pose compose(const Pose& outer, const Pose& inner)
{
    Pose p;
    p.R = outer.R * inner.R;
    p.t = outer.apply(inner.t);
    return p;
}
}  // namespace

SensorMount Scene::sensorAt(const SensorMount& m, double t_s) const
{
    SensorMount out = m;
    if (m.robot >= 0) {
        out.pose = compose(robots[size_t(m.robot)].at(t_s), m.pose);
        out.robot = -1;
    }
    return out;
}

Camera Scene::cameraAt(const Camera& c, double t_s) const
{
    Camera out = c;
    if (c.robot >= 0) {
        out.pose = compose(robots[size_t(c.robot)].at(t_s), c.pose);
        out.robot = -1;
    }
    return out;
}

const Camera* Scene::findCamera(const std::string& name) const
{
    for (const auto& c : cameras)
        if (name.empty() || c.name == name) return &c;
    return nullptr;
}

int Scene::findSurface(const std::string& name) const
{
    for (size_t i = 0; i < surfaces.size(); ++i)
        if (surfaces[i].name == name) return int(i);
    return -1;
}

int Scene::findSensor(const std::string& key) const
{
    for (size_t i = 0; i < sensors.size(); ++i)
        if (sensors[i].name == key) return int(i);
    for (size_t i = 0; i < sensors.size(); ++i)
        if (sensorTypeName(sensors[i].config.type) == key) return int(i);
    return -1;
}

}  // namespace smokescan
