#include "smokescan/scene/scene.hpp"

#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"

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
/// A sensor or camera with its pose in the world at t_s: on its robot, when it rides on one.
template <class T>
T placed(const std::vector<Robot>& robots, const T& x, double t_s)
{
    T out = x;
    if (x.robot >= 0) {
        const Pose r = robots[size_t(x.robot)].at(t_s);
        out.pose.R = r.R * x.pose.R;
        out.pose.t = r.apply(x.pose.t);
        out.robot = -1;
    }
    return out;
}
}  // namespace

SensorMount Scene::sensorAt(const SensorMount& m, double t_s) const { return placed(robots, m, t_s); }

Camera Scene::cameraAt(const Camera& c, double t_s) const { return placed(robots, c, t_s); }

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

void Scene::checkSpan(double from_s, double to_s) const
{
    auto outside = [&](const char* option, double t) {
        if (t < t_start_s) throw Error(option, fmt("%.12g s is before the scene's start, %.12g s", t, t_start_s));
        if (t > t_end_s) throw Error(option, fmt("%.12g s is after the scene's end, %.12g s", t, t_end_s));
    };
    outside("--from", from_s);
    outside("--to", to_s);
    if (!(to_s >= from_s)) throw Error("--to", "must not precede --from");
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
