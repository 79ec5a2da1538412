#pragma once
/// @file scene.hpp
/// @brief Everything a scene file describes: materials, surfaces, sensors, lights, cameras,
/// smoke volumes and the time line. Units: metres, seconds, degrees where named `_deg`.
/// The file format is documented field by field in docs/scene-format.md.
#include <cmath>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "smokescan/core/ray.hpp"
#include "smokescan/media/smoke.hpp"
#include "smokescan/scene/camera_sensor.hpp"
#include "smokescan/scene/trajectory.hpp"
#include "smokescan/sensor_config/sensor_config.hpp"

namespace smokescan {

/// Surface optics.
///
/// | field        | default        | unit | meaning                                              |
/// |--------------|----------------|------|------------------------------------------------------|
/// | albedo       | (0.5,0.5,0.5)  | –    | diffuse reflectance, linear RGB                      |
/// | nir_785      | 0.5            | –    | diffuse reflectance at 785 nm (Hokuyo)               |
/// | nir_905      | 0.5            | –    | diffuse reflectance at 905 nm (Sick)                 |
/// | specular     | 0              | –    | weight of the glossy/specular lobe (metals, gold paper) |
/// | roughness    | 0.5            | –    | roughness of that lobe (0 mirror … 1 diffuse-like)   |
struct Material {
    std::string name;
    Vec3 albedo = Vec3::Constant(0.5);
    double nir_785 = 0.5;
    double nir_905 = 0.5;
    double specular = 0.0;
    double roughness = 0.5;
};

struct BoxShape {
    Vec3 size_m = Vec3::Ones();
};  ///< centred on the pose
struct QuadShape {
    Vec3 corner_m, edge_u_m, edge_v_m;
};  ///< world coordinates
struct CylinderShape {
    double radius_m = 0.05, height_m = 1.0;
};  ///< axis +z from the pose
struct MeshShape {
    std::string obj_path;
    double scale = 1.0;
};

struct Surface {
    std::string name;
    int material = 0;  ///< index into Scene::materials
    Pose pose;
    std::variant<BoxShape, QuadShape, CylinderShape, MeshShape> shape;
};

/// A laser range finder mounted in the scene. The beam plane is the sensor's local x–y plane,
/// angle 0 along local +x. What the sensor is and does lives in its config.
struct SensorMount {
    std::string name;
    Pose pose;  ///< in the world, or in its robot's frame when it rides on one
    SensorConfig config;
    int robot = -1;  ///< index into Scene::robots, or −1: fixed in the world

    /// World ray of the beam at `angle_rad` in the sensor's scan plane (local x–y, 0 = local +x).
    Ray beamRay(double angle_rad) const
    {
        return Ray{pose.t, pose.rotate(Vec3(std::cos(angle_rad), std::sin(angle_rad), 0.0)).normalized()};
    }
};

/// How a light emits (scene files: kind = "area", "point", "spot", "directional", "ambient").
enum class LightKind { Area, Point, Spot, Directional, Ambient };

/// @brief The kind a scene file names, or nothing for an unknown name.
std::optional<LightKind> parseLightKind(const std::string& name);

struct Light {
    std::string name;
    LightKind kind = LightKind::Area;
    Pose pose;  ///< area: centre, emitting along local +x; spot: axis local +x
    double width_m = 0.6, height_m = 0.04;  ///< area light extent (local y, z)
    double power_w = 70.0;  ///< electrical power; radiant = power_w · efficiency
    double efficiency = 0.25;  ///< fraction of power radiated as visible light
    Vec3 color = Vec3::Ones();  ///< linear RGB tint
    double spot_angle_deg = 30;  ///< spot half angle
    double radiance = 1.0;  ///< ambient: uniform radiance [W/(m²·sr)]
    double irradiance = 1.0;  ///< directional: irradiance normal to the beam [W/m²], along local +x
};

/// The projection of a scene camera (scene files: kind = "pinhole", "omni").
enum class CameraKind { Pinhole, Omni };

/// @brief The kind a scene file names, or nothing for an unknown name.
std::optional<CameraKind> parseCameraKind(const std::string& name);

/// A scene camera. Pinhole: looks along local +x, local +z up (image left = local +y). Omni: a
/// single-viewpoint catadioptric camera (paraboloidal mirror, Nayar) whose viewpoint is the pose's
/// position, its mirror axis local −z (straight down), local +x to the image's right and local +y
/// up the image (a map seen from above); render/omni_camera.hpp.
struct Camera {
    std::string name;
    CameraKind kind = CameraKind::Pinhole;
    Pose pose;  ///< in the world, or in its robot's frame when it rides on one
    int robot = -1;  ///< index into Scene::robots, or −1: fixed in the world
    int width = 640, height = 480;
    double hfov_deg = 60.0;
    double fx_px = 0, fy_px = 0;  ///< focal lengths [px]; 0 = from hfov_deg (fy = fx)
    double cx_px = -1, cy_px = -1;  ///< principal point (omni: image centre) [px]; < 0 = the image centre
    double mirror_radius_px = 192;  ///< omni: R, the image radius of the 90° incidence circle [px]
    double max_incidence_deg = 110;  ///< omni: the mirror's rim, incidence from straight down [deg]
    double base_radius_px = 0;  ///< omni: the robot's base hides the image within this radius [px]
    CameraSensor sensor;  ///< exposure, noise, white balance, encoding (camera_sensor.hpp)
};

struct Scene {
    std::string source;  ///< file path or "builtin:NAME", for messages
    std::vector<Material> materials;
    std::vector<Surface> surfaces;
    std::vector<SensorMount> sensors;
    std::vector<Light> lights;
    std::vector<Camera> cameras;
    std::vector<SmokeVolume> volumes;
    std::vector<Robot> robots;
    double t_start_s = 0, t_end_s = 60;

    /// @brief Refuses a run's times outside the scene's time line: `from_s` [s] before its start or
    /// after its end, `to_s` [s] likewise, `to_s` before `from_s`.
    /// @throw Error naming --from or --to.
    void checkSpan(double from_s, double to_s) const;
    /// @brief Index of the sensor with this name, else of the first of this type; −1 if none.
    int findSensor(const std::string& name_or_type) const;
    /// @brief The sensor at time t_s, its pose in the world (on its robot, when it rides on one).
    SensorMount sensorAt(const SensorMount& m, double t_s) const;
    /// @brief The camera at time t_s, its pose in the world (on its robot, when it rides on one).
    Camera cameraAt(const Camera& c, double t_s) const;
    /// @brief Index of the surface with this name; −1 if none.
    int findSurface(const std::string& name) const;
    /// @brief The camera with this name ("" = the first); null if none.
    const Camera* findCamera(const std::string& name) const;
};

}  // namespace smokescan
