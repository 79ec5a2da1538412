// Scene files: TOML, read strictly (unknown keys, wrong types and missing fields are errors).
// The format is documented in docs/scene-format.md.
#include "smokescan/scene/scene_io.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include "sensor_tables.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/io/text_input.hpp"
#include "smokescan/scene/mesh.hpp"
#include "smokescan/sensor_config/laser_kind.hpp"
#include "smokescan/sensor_config/sensor_file.hpp"
#include "toml_reader.hpp"

namespace smokescan {
namespace {

namespace fs = std::filesystem;

/// Pose from `position` and either `rpy_deg` or `look_at` (local +x towards it, +z up).
/// A point (or an extent) within limits::kSceneReach_m of the origin; `def` when the key is absent,
/// required when there is no `def`.
Vec3 placed(TomlTable& t, const std::string& key, const std::optional<Vec3>& def = std::nullopt)
{
    const Vec3 p = def ? t.vec3(key, *def) : t.vec3Req(key);
    if (!(p.cwiseAbs().maxCoeff() <= limits::kSceneReach_m)) t.error(key, "must lie within 1000 km of the origin");
    return p;
}

Pose readPose(TomlTable& t, const Vec3& def_pos = Vec3::Zero())
{
    const Vec3 p = placed(t, "position", def_pos);
    if (t.has("look_at")) {
        if (t.has("rpy_deg")) t.error("rpy_deg", "conflicts with look_at: give one");
        const Vec3 x = placed(t, "look_at", p) - p;
        if (x.norm() < 1e-9) t.error("look_at", "must differ from position");
        const Vec3 fx = x.normalized();
        Vec3 fy = Vec3::UnitZ().cross(fx);
        if (fy.norm() < 1e-9) fy = Vec3::UnitY();
        fy.normalize();
        Pose pose;
        pose.R.col(0) = fx;
        pose.R.col(1) = fy;
        pose.R.col(2) = fx.cross(fy);
        pose.t = p;
        return pose;
    }
    return Pose::fromRpyDeg(p, t.vec3("rpy_deg", Vec3::Zero()));
}

std::string resolve(const std::string& base_dir, const std::string& p)
{
    if (p.empty() || fs::path(p).is_absolute() || base_dir.empty()) return p;
    return (fs::path(base_dir) / p).lexically_normal().string();
}

Material readMaterial(TomlTable t)
{
    Material m;
    m.name = t.strReq("name");
    m.albedo = t.vec3("albedo", m.albedo);
    if ((m.albedo.array() < 0).any() || (m.albedo.array() > 1).any()) t.error("albedo", "must lie in [0, 1]");
    auto unit = [&](const char* key, double def) {
        const double v = t.num(key, def);
        if (v < 0 || v > 1) t.error(key, "must lie in [0, 1]");
        return v;
    };
    m.nir_785 = unit("nir_785", m.nir_785);
    m.nir_905 = unit("nir_905", m.nir_905);
    m.specular = unit("specular", m.specular);
    m.roughness = unit("roughness", m.roughness);
    t.finish();
    return m;
}

Surface readSurface(TomlTable t, const std::map<std::string, int>& materials, const std::string& base_dir)
{
    Surface s;
    s.name = t.strReq("name");
    const std::string mat = t.strReq("material");
    const auto it = materials.find(mat);
    if (it == materials.end()) t.error("material", "names no material: '" + mat + "'");
    s.material = it->second;
    const std::string type = t.strReq("type");
    if (type == "box") {
        s.pose = readPose(t);
        BoxShape b;
        b.size_m = t.vec3Req("size");
        if ((b.size_m.array() <= 0).any() || !(b.size_m.maxCoeff() <= 2 * limits::kSceneReach_m))
            t.error("size", "must be > 0 on every axis and at most 2000 km");
        s.shape = b;
    } else if (type == "quad") {
        QuadShape q{placed(t, "corner"), placed(t, "u"), placed(t, "v")};
        if (q.edge_u_m.cross(q.edge_v_m).norm() < 1e-12) t.error("u", "and v must span a parallelogram");
        s.shape = q;
    } else if (type == "cylinder") {
        s.pose = readPose(t);
        s.shape = CylinderShape{t.between("radius", 0.05, 1e-6, 1e3), t.between("height", 1.0, 1e-6, 1e3)};
    } else if (type == "mesh") {
        s.pose = readPose(t);
        MeshShape m{resolve(base_dir, t.strReq("file")), t.between("scale", 1.0, 1e-9, 1e6)};
        s.shape = m;
    } else {
        t.error("type", "must be box, quad, cylinder or mesh, got '" + type + "'");
    }
    t.finish();
    return s;
}

/// The robot a sensor or camera rides on (`robot = "name"`), or −1.
int readRobotRef(TomlTable& t, const std::vector<Robot>& robots)
{
    if (!t.has("robot")) return -1;
    const std::string name = t.strReq("robot");
    for (size_t i = 0; i < robots.size(); ++i)
        if (robots[i].name == name) return int(i);
    t.error("robot", "names no robot of the scene: '" + name + "'");
}

Robot readRobot(TomlTable t)
{
    Robot r;
    r.name = t.strReq("name");
    auto frames = t.tables("keyframes");
    if (frames.empty()) t.error("keyframes", "needs at least one keyframe");
    if (int64_t(frames.size()) > limits::kKeyframes)
        t.error("keyframes", "more than " + std::to_string(limits::kKeyframes) + " keyframes");
    for (auto& f : frames) {
        Keyframe k;
        k.time_s = f.numReq("time_s");
        k.position = placed(f, "position", k.position);
        k.yaw_deg = f.num("yaw_deg", 0.0);
        if (!r.keyframes.empty() && !(k.time_s > r.keyframes.back().time_s))
            f.error("time_s", "must exceed the previous keyframe's");
        if (!k.position.allFinite()) f.error("position", "must be finite");
        f.finish();
        r.keyframes.push_back(k);
    }
    t.finish();
    return r;
}

SensorMount readSensor(TomlTable t, const std::string& base_dir, const std::vector<Robot>& robots)
{
    const std::string type = t.strReq("type");
    const auto kind = parseSensorType(type);
    if (!kind) t.error("type", std::string("must be ") + sensorTypeNames() + ", got '" + type + "'");
    SensorMount m;
    m.config = SensorConfig::defaults(*kind);
    m.name = t.str("name", type);
    m.pose = readPose(t);
    m.robot = readRobotRef(t, robots);
    if (t.has("sensor_file")) applySensorFile(resolve(base_dir, t.strReq("sensor_file")), m.config);
    readSceneSensorKeys(t, m.config);
    t.finish(laserKind(*kind).withArticle() + " sensor");
    return m;
}

/// A light: the keys every kind has, then its own kind's (any other kind's key is refused).
/// Bounds: power 1 MW, radiance and irradiance 1e6 (the sun gives about 1e3 W/m²), colour
/// gains 100, extents 1 km.
Light readLight(TomlTable t)
{
    Light l;
    l.name = t.strReq("name");
    const std::string kind = t.strReq("kind");
    const auto k = parseLightKind(kind);
    if (!k) t.error("kind", "must be area, point, spot, directional or ambient, got '" + kind + "'");
    l.kind = *k;
    l.color = t.vec3("color", l.color);
    if (!(l.color.minCoeff() >= 0 && l.color.maxCoeff() <= 100)) t.error("color", "must be 3 gains in [0, 100]");
    auto radiant = [&] {
        l.power_w = t.between("power_w", l.power_w, 0, 1e6);
        l.efficiency = t.between("efficiency", l.efficiency, 0, 1);
    };
    switch (l.kind) {
    case LightKind::Area:
        l.pose = readPose(t);
        l.width_m = t.between("width", l.width_m, 1e-6, 1e3);
        l.height_m = t.between("height", l.height_m, 1e-6, 1e3);
        radiant();
        break;
    case LightKind::Point:
        l.pose = readPose(t);
        radiant();
        break;
    case LightKind::Spot:
        l.pose = readPose(t);
        l.spot_angle_deg = t.between("spot_angle_deg", l.spot_angle_deg, 1e-3, 180);
        radiant();
        break;
    case LightKind::Directional:
        l.pose = readPose(t);
        l.irradiance = t.between("irradiance", l.irradiance, 0, 1e6);
        break;
    case LightKind::Ambient:
        l.radiance = t.between("radiance", l.radiance, 0, 1e6);
        break;
    }
    t.finish((l.kind == LightKind::Area || l.kind == LightKind::Ambient ? "an " : "a ") + kind + " light");
    return l;
}

CameraSensor readCameraSensor(TomlTable t)
{
    CameraSensor s;
    s.exposure = t.nonneg("exposure", s.exposure);
    if (s.exposure > 1e6) t.error("exposure", "must be in [0, 1e6] (0: auto)");
    s.meter_grey = t.positive("meter_grey", s.meter_grey);
    if (s.meter_grey < 1e-4 || s.meter_grey > 1) t.error("meter_grey", "must be in [1e-4, 1]");
    s.full_well_e = t.positive("full_well_e", s.full_well_e);
    if (s.full_well_e < 10 || s.full_well_e > 1e7) t.error("full_well_e", "must be in [10, 1e7] electrons");
    s.read_noise_e = t.nonneg("read_noise_e", s.read_noise_e);
    if (s.read_noise_e > 1e4) t.error("read_noise_e", "must be in [0, 1e4] electrons");
    const Vec3 wb = t.vec3("white_balance", Vec3(1, 1, 1));
    for (int k = 0; k < 3; ++k) {
        if (!(wb[k] > 0 && wb[k] <= 100)) t.error("white_balance", "gains must be in (0, 100]");
        s.white_balance[size_t(k)] = wb[k];
    }
    const long long bits = t.integer("bits", s.bits);
    if (bits < 0 || bits > 16) t.error("bits", "must be in [0, 16] (0: no quantisation)");
    s.bits = int(bits);
    s.noise = t.boolean("noise", s.noise);
    t.finish();
    return s;
}

/// A camera: the keys every kind has, then its own kind's (the other kind's are refused).
Camera readCamera(TomlTable t, const std::vector<Robot>& robots)
{
    Camera c;
    c.name = t.strReq("name");
    const std::string kind = t.str("kind", "pinhole");
    const auto k = parseCameraKind(kind);
    if (!k) t.error("kind", "must be pinhole or omni, got '" + kind + "'");
    c.kind = *k;
    c.pose = readPose(t);
    c.robot = readRobotRef(t, robots);
    for (auto [key, side] : {std::pair<const char*, int*>{"width", &c.width}, {"height", &c.height}}) {
        const long long v = t.integer(key, *side);
        if (v < 1 || v > limits::kFrameSide)
            t.error(key, "must lie in 1…" + std::to_string(limits::kFrameSide) + " px");
        *side = int(v);
    }
    if (int64_t(c.width) * c.height > limits::kFramePixels)
        t.error("height", "makes a frame of more than " + std::to_string(limits::kFramePixels) + " pixels");
    c.cx_px = t.has("cx_px") ? t.between("cx_px", 0, 0, limits::kFrameSide) : -1.0;
    c.cy_px = t.has("cy_px") ? t.between("cy_px", 0, 0, limits::kFrameSide) : -1.0;
    if (c.kind == CameraKind::Pinhole) {
        c.hfov_deg = t.positive("hfov_deg", c.hfov_deg);
        if (c.hfov_deg >= 180) t.error("hfov_deg", "must be < 180");
        c.fx_px = t.between("fx_px", 0.0, 0, 1e7);
        c.fy_px = t.between("fy_px", 0.0, 0, 1e7);
        for (const auto& [key, f] : {std::pair<const char*, double>{"fx_px", c.fx_px}, {"fy_px", c.fy_px}})
            if (f != 0 && f < 1e-3) t.error(key, "must be 0 (from hfov_deg) or >= 1e-3 px");
    } else {
        c.mirror_radius_px = t.positive("mirror_radius_px", c.mirror_radius_px);
        if (c.mirror_radius_px > 1e6) t.error("mirror_radius_px", "must be at most 1e6");
        c.max_incidence_deg = t.positive("max_incidence_deg", c.max_incidence_deg);
        if (c.max_incidence_deg >= 170)
            t.error("max_incidence_deg", "must be < 170 (a paraboloid's image grows without bound towards 180)");
        c.base_radius_px = t.nonneg("base_radius_px", c.base_radius_px);
        if (c.base_radius_px >= c.mirror_radius_px * std::tan(0.5 * c.max_incidence_deg * M_PI / 180))
            t.error("base_radius_px", "hides the whole mirror");
    }
    if (t.has("sensor")) c.sensor = readCameraSensor(t.table("sensor"));
    t.finish(c.kind == CameraKind::Pinhole ? "a pinhole camera" : "an omni camera");
    return c;
}

Medium readMedium(TomlTable& parent)
{
    if (!parent.has("medium")) return Medium::preset("theatrical_fog");
    if (parent.isString("medium")) {
        const std::string name = parent.strReq("medium");
        try {
            return Medium::preset(name);
        } catch (const Error& e) {
            parent.error("medium", e.what());
        }
    }
    TomlTable t = parent.table("medium");
    Medium m = Medium::preset(t.str("preset", "theatrical_fog"));
    m.name = t.str("name", m.name);
    if (t.has("angstrom")) {
        m = Medium::fromAngstrom(m.name, t.positive("sigma_t_550", m.sigma_t_550), t.numReq("angstrom"), m.albedo, m.g);
    } else {
        m.sigma_t_550 = t.nonneg("sigma_t_550", m.sigma_t_550);
        m.sigma_t_785 = t.nonneg("sigma_t_785", m.sigma_t_785);
        m.sigma_t_905 = t.nonneg("sigma_t_905", m.sigma_t_905);
    }
    m.albedo = t.nonneg("albedo", m.albedo);
    if (m.albedo > 1) t.error("albedo", "must lie in [0, 1]");
    m.g = t.num("g", m.g);
    if (m.g <= -1 || m.g >= 1) t.error("g", "must lie in (-1, 1)");
    m.lidar_ratio_sr = t.nonneg("lidar_ratio_sr", m.lidar_ratio_sr);
    t.finish();
    return m;
}

/// A smoke area's grid, bounded before it is made: at most limits::kGridSide voxels a side
/// (its soft edge included), within 1000 km of the origin.
void checkGridExtent(TomlTable& t, const Vec3& lo, const Vec3& hi, double voxel_m, double edge_m,
                     const std::string& what)
{
    if (!(((hi - lo).maxCoeff() + 2 * edge_m) / voxel_m <= limits::kGridSide))
        t.error(edge_m > 0 ? "edge_m" : "voxel",
                "makes this " + what + " over 4000 voxels a side (its soft edge included)");
    const double reach = std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()) + edge_m;
    if (!(reach <= 1e6))
        t.error(what == "box" ? "max" : "file", "the " + what + " must lie within 1000 km of the origin");
}

/// The memory a box or mesh area's grid is estimated to take [bytes]: its interior is constant
/// tiles, its surface a shell of dense 8³ leaves (about 2.3 KB each) as thick as the soft edge
/// (both sides) plus a voxel, the area taken as its bounding box's.
double gridBytes(const Vec3& lo, const Vec3& hi, double voxel_m, double edge_m)
{
    const Vec3 n = (hi - lo) / voxel_m + Vec3::Constant(2 * edge_m / voxel_m + 2);
    const double area = 2 * (n.x() * n.y() + n.y() * n.z() + n.z() * n.x());
    const double layers = std::ceil((2 * edge_m / voxel_m + 2) / 8);
    return area / 64 * layers * 2.3e3;
}

/// Adds a grid's estimated memory to the scene's total, refusing (on the table's `voxel`) a total
/// beyond limits::kGridBytes.
void addGridBytes(TomlTable& t, double& total, const Vec3& lo, const Vec3& hi, double voxel_m, double edge_m)
{
    total += gridBytes(lo, hi, voxel_m, edge_m);
    if (total > limits::kGridBytes)
        t.error("voxel",
                "makes the scene's box and mesh smoke take about " + fmt("%.1f", total / 1e9) +
                    " GB of grid (at most " + fmt("%.1f", limits::kGridBytes / 1e9) +
                    " over all of them): raise voxel or narrow edge_m");
}

/// A smoke area's density [engine units], within limits::kDensity.
double density(TomlTable& t)
{
    const double rho = t.nonneg("density", 1.0);
    if (rho > limits::kDensity)
        t.error("density", "must be at most 1e6 (engine units; the paper's threshold is 0.0028)");
    return rho;
}

DensityTimeline readTimeline(TomlTable& parent)
{
    if (!parent.has("timeline")) return DensityTimeline::constant();
    TomlTable t = parent.table("timeline");
    const std::string kind = t.strReq("kind");
    try {
        if (kind == "constant") {
            const double v = t.between("value", 1.0, 0, limits::kDensity);
            t.finish();
            return DensityTimeline::constant(v);
        }
        if (kind == "keyframes") {
            const std::string interp = t.str("interp", "linear");
            DensityTimeline::Interp i = DensityTimeline::Interp::Linear;
            if (interp == "step")
                i = DensityTimeline::Interp::Step;
            else if (interp == "exp")
                i = DensityTimeline::Interp::Exp;
            else if (interp != "linear")
                t.error("interp", "must be linear, step or exp");
            auto keys = t.pairs("keys");
            for (const auto& [time_s, factor] : keys)
                if (!(factor >= 0 && factor <= limits::kDensity))
                    t.error(
                        "keys",
                        "factors must be in [0, 1e6], got " + fmt("%g", factor) + " at " + fmt("%g", time_s) + " s");
            const double decay = t.nonneg("decay_s", 0.0);
            t.finish();
            return DensityTimeline::keyframes(keys, i, decay);
        }
        if (kind == "machine") {
            auto on = t.pairs("on");
            const double fill = t.positive("fill_per_s", 1.0), dissolve = t.positive("dissolve_s", 60.0);
            t.finish();
            return DensityTimeline::machine(on, fill, dissolve);
        }
    } catch (const Error& e) {
        if (std::string(e.what()).rfind(t.source(), 0) == 0) throw;
        t.error(e.what());
    }
    t.error("kind", "must be constant, keyframes or machine, got '" + kind + "'");
}

/// One [[smoke]] table; `grid_bytes` (the scene's boxes' grids, counted before any was made) adds
/// each mesh's grid, bounded (limits::kGridBytes) before it is made.
SmokeVolume readSmoke(TomlTable t, const std::string& base_dir, double& grid_bytes)
{
    SmokeVolume v;
    v.name = t.strReq("name");
    const std::string type = t.strReq("type");
    const std::string role = t.str("role", type == "plume" ? "local" : "regional");
    if (role == "regional")
        v.role = SmokeRole::Regional;
    else if (role == "local")
        v.role = SmokeRole::Local;
    else
        t.error("role", "must be regional or local, got '" + role + "'");
    v.medium = readMedium(t);
    v.timeline = readTimeline(t);
    try {
        if (type == "box") {
            const Vec3 lo = t.vec3Req("min"), hi = t.vec3Req("max");
            if (!(hi.array() > lo.array()).all()) t.error("max", "must exceed min on every axis");
            const double rho = density(t), h = t.positive("voxel", 0.05), edge = t.nonneg("edge_m", 0.0);
            checkGridExtent(t, lo, hi, h, edge, "box");  // its grid was counted before any was made
            v.source = std::make_shared<const DensityGrid>(DensityGrid::box(lo, hi, rho, h, edge));
        } else if (type == "mesh") {
            const std::string file = resolve(base_dir, t.strReq("file"));
            v.file = file;
            const Pose pose = readPose(t);
            const double scale = t.positive("scale", 1.0);
            const double rho = density(t), h = t.positive("voxel", 0.05), edge = t.nonneg("edge_m", 0.0);
            TriMesh mesh = loadObj(file);
            for (Vec3& p : mesh.points_m) p = pose.apply(scale * p);
            Aabb box;
            for (const Vec3& p : mesh.points_m) box.extend(p);
            if (!box.empty()) {
                checkGridExtent(t, box.lo, box.hi, h, edge, "mesh");
                addGridBytes(t, grid_bytes, box.lo, box.hi, h, edge);
            }
            if (const size_t open = openEdges(mesh))
                t.error("file",
                        "'" + file + "' is not a closed mesh (" + std::to_string(open) +
                            " edges do not join exactly two faces); a smoke area needs an inside");
            v.source =
                std::make_shared<const DensityGrid>(DensityGrid::fromMesh(mesh.points_m, mesh.triangles, rho, h, edge));
        } else if (type == "vdb") {
            VdbLoadConfig c;
            const std::string file = resolve(base_dir, t.strReq("file"));
            v.file = file;
            c.grid_name = t.str("grid", c.grid_name);
            c.scale = t.positive("scale", 1.0);
            v.source = std::make_shared<const DensityGrid>(DensityGrid::loadVdb(file, c));
        } else if (type == "plume") {
            PlumeConfig p;
            p.source_m = t.vec3Req("source");
            p.rate_per_s = t.num("rate_per_s", p.rate_per_s);
            p.lifetime_s = t.num("lifetime_s", p.lifetime_s);
            p.rise_m_s = t.num("rise_m_s", p.rise_m_s);
            p.wind_m_s = t.vec3("wind_m_s", p.wind_m_s);
            p.spread_m_s = t.num("spread_m_s", p.spread_m_s);
            p.radius_m = t.num("radius_m", p.radius_m);
            p.growth_m_s = t.num("growth_m_s", p.growth_m_s);
            p.peak_density = t.num("peak_density", p.peak_density);
            if (p.peak_density > limits::kDensity) t.error("peak_density", "must be at most 1e6");
            p.start_s = t.num("start_s", p.start_s);
            p.stop_s = t.num("stop_s", 1e300);
            p.voxel_m = t.num("voxel", p.voxel_m);
            p.seed = uint64_t(t.integer("seed", 1));
            p.validate();
            v.source = p;
        } else {
            t.error("type", "must be box, mesh, vdb or plume, got '" + type + "'");
        }
    } catch (const Error& e) {
        const std::string msg = e.what();
        if (msg.rfind(t.source(), 0) == 0 || msg.find(".vdb:") != std::string::npos ||
            msg.find(".obj:") != std::string::npos)
            throw;
        t.error(msg);
    }
    t.finish();
    return v;
}

}  // namespace

Scene parseScene(const std::string& text, const std::string& source, const std::string& base_dir)
{
    const toml::table root = parseToml(text, source);
    TomlTable top(root, source, "");
    Scene s;
    s.source = source;
    if (top.has("scene")) {
        TomlTable h = top.table("scene");
        h.str("name", "");
        h.str("description", "");
        s.t_start_s = h.num("t_start_s", s.t_start_s);
        s.t_end_s = h.num("t_end_s", s.t_end_s);
        if (!(s.t_end_s > s.t_start_s)) h.error("t_end_s", "must exceed t_start_s");
        h.finish();
    }
    std::map<std::string, int> mats;
    for (auto& t : top.tables("materials")) {
        Material m = readMaterial(t);
        if (mats.count(m.name)) t.error("name", "repeats material '" + m.name + "'");
        mats[m.name] = int(s.materials.size());
        s.materials.push_back(m);
    }
    for (auto& t : top.tables("surfaces")) s.surfaces.push_back(readSurface(t, mats, base_dir));
    for (auto& t : top.tables("robots")) {
        s.robots.push_back(readRobot(t));
        for (size_t i = 0; i + 1 < s.robots.size(); ++i)
            if (s.robots[i].name == s.robots.back().name)
                t.error("name", "repeats robot '" + s.robots.back().name + "'");
    }
    for (auto& t : top.tables("sensors")) s.sensors.push_back(readSensor(t, base_dir, s.robots));
    for (auto& t : top.tables("lights")) s.lights.push_back(readLight(t));
    for (auto& t : top.tables("cameras")) s.cameras.push_back(readCamera(t, s.robots));
    // The boxes' grids are counted together before the first is made (a mesh's, whose extent
    // needs its file, as it is read).
    double plume_voxels = 0, grid_bytes = 0;
    for (auto& t : top.tables("smoke")) {
        if (!t.has("type") || t.str("type", "") != "box" || !t.has("min") || !t.has("max")) continue;
        const Vec3 lo = t.vec3Req("min"), hi = t.vec3Req("max");
        const double h = t.num("voxel", 0.05), edge = t.num("edge_m", 0.0);
        // A box refused on its own (its extent, its keys) is refused with its key below.
        if (!((hi.array() > lo.array()).all() && h > 0 && edge >= 0 &&
              ((hi - lo).maxCoeff() + 2 * edge) / h <= limits::kGridSide))
            continue;
        addGridBytes(t, grid_bytes, lo, hi, h, edge);
    }
    for (auto& t : top.tables("smoke")) {
        s.volumes.push_back(readSmoke(t, base_dir, grid_bytes));
        if (const auto* p = std::get_if<PlumeConfig>(&s.volumes.back().source)) plume_voxels += p->voxelBound();
        if (plume_voxels > limits::kPlumeVoxels)
            t.error("the scene's plumes would cover about " + limits::count(plume_voxels) +
                    " voxels at once (at most 5e8 over all of them): raise their voxel or lower radius_m, "
                    "growth_m_s or rate_per_s");
    }
    top.finish();
    return s;
}

std::vector<std::string> sceneFiles(const Scene& s)
{
    std::vector<std::string> f;
    for (const Surface& x : s.surfaces)
        if (const auto* m = std::get_if<MeshShape>(&x.shape)) f.push_back(m->obj_path);
    for (const SensorMount& m : s.sensors)
        if (!m.config.sensor_file.empty()) f.push_back(m.config.sensor_file);
    for (const SmokeVolume& v : s.volumes)
        if (!v.file.empty()) f.push_back(v.file);
    return f;
}

Scene loadScene(const std::string& name_or_path)
{
    for (const auto& b : builtinSceneNames())
        if (b == name_or_path)
            return parseScene(builtinSceneText(b), "builtin:" + b, "");  // self-contained: no file paths
    if (!fs::exists(name_or_path))
        throw Error(
            name_or_path,
            "no such scene file (built-in scenes: " +
                [] {
                    std::string s;
                    for (const auto& b : builtinSceneNames()) s += (s.empty() ? "" : ", ") + b;
                    return s;
                }() +
                ")");
    return parseScene(readTextInput(name_or_path, "scene file", limits::kTomlInputBytes), name_or_path,
                      fs::path(name_or_path).parent_path().string());
}

}  // namespace smokescan
