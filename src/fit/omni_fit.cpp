#include "smokescan/fit/omni_fit.hpp"

#include <cmath>
#include <map>

#include "smokescan/core/error.hpp"
#include "smokescan/core/order_stats.hpp"
#include "smokescan/media/smoke.hpp"
#include "smokescan/omni/range_tally.hpp"
#include "smokescan/omni/scanline_truth.hpp"
#include "smokescan/plot/format.hpp"

namespace smokescan {
namespace {

/// The scene's omni camera by name, or its first; its pose must hold over the log.
const Camera& standingCamera(const Scene& scene, const RecordedLog& log, const std::string& name)
{
    const Camera* cam = nullptr;
    for (const Camera& c : scene.cameras)
        if (c.kind == CameraKind::Omni && (name.empty() || c.name == name)) {
            cam = &c;
            break;
        }
    if (!cam)
        throw Error(
            scene.source,
            name.empty() ? std::string("has no omni camera (kind = \"omni\")") : "has no omni camera '" + name + "'");
    const Pose p0 = scene.cameraAt(*cam, log.scans.front().time_s).pose;
    for (const LaserLogScan& s : log.scans) {
        const Pose p = scene.cameraAt(*cam, s.time_s).pose;
        if ((p.t - p0.t).norm() > 1e-3 || (p.R - p0.R).norm() > 1e-4)
            throw Error(log.path,
                        fmt("was made by a moving camera: '%s' moves by %.3f s; fit reads an omnicam that "
                            "stands still (its groups are bearings that keep their surface)",
                            cam->name.c_str(), s.time_s));
    }
    return *cam;
}

void checkConfig(const OmniFitConfig& c)
{
    if (!std::isfinite(c.floor_z_m) || std::abs(c.floor_z_m) > 1e4) throw Error("--floor-z", "must be within ±10 km");
    if (!(c.max_range_m >= 0.01 && c.max_range_m <= 1000)) throw Error("--max-range", "must be in [0.01, 1000] m");
    if (!(c.tolerance_m >= 0.001 && c.tolerance_m <= 100)) throw Error("--tolerance", "must be in [0.001, 100] m");
}

/// Most readings beyond the maximum range: the log's unit is not the one given.
void checkUnit(const RecordedLog& log, double max_range_m)
{
    long long n = 0, beyond = 0;
    for (const LaserLogScan& s : log.scans)
        for (double v : s.range) {
            ++n;
            beyond += v * log.unit_m > 1.05 * max_range_m;
        }
    if (beyond > n / 5)
        throw Error(log.path,
                    fmt("reads beyond the omnicam's %.1f m in %lld of its %lld readings: is --unit (or "
                        "--max-range) right?",
                        max_range_m, beyond, n));
}

/// Groups from the truth: per surface named prefix*, the scanlines within the maximum range whose
/// neighbours see the same surface, each an interval of its own bearing.
std::vector<BeamGroup> truthGroups(const Scene& scene, const OmniFitInputs& o, const std::vector<double>& angle,
                                   const std::string& prefix, double max_range_m, double tolerance_m)
{
    std::vector<BeamGroup> out;
    std::map<int, size_t> index;
    const size_t n = angle.size();
    for (size_t i = 0; i < n; ++i) {
        const int s = o.surface[i];
        if (s < 0 || !(o.truth_m[i] < max_range_m - tolerance_m)) continue;
        if (scene.surfaces[size_t(s)].name.rfind(prefix, 0) != 0) continue;
        if (i == 0 || i + 1 == n || o.surface[i - 1] != s || o.surface[i + 1] != s) continue;
        auto [it, added] = index.emplace(s, out.size());
        if (added) {
            const Surface& sf = scene.surfaces[size_t(s)];
            out.push_back(BeamGroup{sf.name, {}, 0, scene.materials[size_t(sf.material)].name});
        }
        out[it->second].intervals_rad.emplace_back(angle[i], angle[i]);
    }
    if (out.empty())
        throw Error(scene.source,
                    fmt("no scanline of the omni camera '%s' sees a surface named '%s*' within "
                        "%.1f m",
                        o.camera.c_str(), prefix.c_str(), max_range_m));
    return out;
}

/// The groups the user gave (bearings in degrees, as the log has them; no range: the truth's).
std::vector<BeamGroup> userGroups(const FitInputsConfig& cfg, FitSources& sources)
{
    std::vector<BeamGroup> groups;
    if (!cfg.surfaces_file.empty()) groups = readBeamGroupFile(cfg.surfaces_file);
    for (const auto& s : cfg.surfaces) groups.push_back(parseBeamGroup(s));
    for (const BeamGroup& g : groups)
        if (g.range_m > 0)
            throw Error(
                cfg.surfaces.empty() ? cfg.surfaces_file : std::string("--surface"),
                "group '" + g.name + "' gives a range: the omnicam's distances and lines of sight come from the scene");
    sources.groups_from = cfg.surfaces_file.empty() ? std::string("--surface") : cfg.surfaces_file;
    return groups;
}

}  // namespace

OmniFitInputs loadOmniFitInputs(const FitInputsConfig& cfg, const OmniFitConfig& omni)
{
    checkConfig(omni);
    if (cfg.scene.empty())
        throw Error("--sensor-type omnicam", "needs --scene (the omnicam's truth: what each scanline should read)");
    OmniFitInputs o;
    o.in = loadFitData(cfg);
    const RecordedLog& log = o.in.log;
    const Scene& scene = *o.in.scene;
    checkUnit(log, omni.max_range_m);
    const Camera& cam = standingCamera(scene, log, omni.camera);
    o.camera = cam.name;
    const Pose pose = scene.cameraAt(cam, log.scans.front().time_s).pose;
    o.height_m = pose.t.z() - omni.floor_z_m;
    if (!(o.height_m > 0))
        throw Error("--floor-z",
                    fmt("puts the floor at or above the omni camera '%s' (at %.3f m)", cam.name.c_str(), pose.t.z()));
    // The truth is the geometry's: smoke does not move an obstacle.
    const std::vector<double>& angle = log.scans.front().angle_rad;
    const ScanlineTruth truth = scanlineTruth(*o.in.surfaces, SmokeField{}, pose, o.height_m, angle, omni.max_range_m);
    o.truth_m = truth.range_m;
    o.surface = truth.surface;
    for (double d : o.truth_m) o.sight_m.push_back(std::hypot(std::min(d, omni.max_range_m), o.height_m));
    for (const LaserLogScan& s : log.scans) {
        std::vector<bool> f(s.range.size());
        for (size_t i = 0; i < f.size(); ++i) {
            const ReadingOutcome c =
                classifyReading(s.range[i] * log.unit_m, o.truth_m[i], omni.max_range_m, omni.tolerance_m);
            f[i] = c != ReadingOutcome::Ok;
            o.shorter += c == ReadingOutcome::Short;
            o.longer += c == ReadingOutcome::Long;
        }
        o.readings += (long long)f.size();
        o.failed.push_back(std::move(f));
    }
    o.in.groups = cfg.surfaces.empty() && cfg.surfaces_file.empty()
        ? truthGroups(scene, o, angle, cfg.prefix, omni.max_range_m, omni.tolerance_m)
        : userGroups(cfg, o.in.sources);
    if (o.in.sources.groups_from.empty()) o.in.sources.groups_from = scene.source;
    for (BeamGroup& g : o.in.groups) {
        std::vector<double> sight;
        for (size_t i = 0; i < angle.size(); ++i)
            if (g.contains(angle[i])) sight.push_back(o.sight_m[i]);
        if (!sight.empty()) g.range_m = median(std::move(sight));
    }
    o.spec.n_beams = int(angle.size());
    o.spec.range_max_m = omni.max_range_m;
    std::vector<double> dt;
    for (size_t k = 1; k < log.scans.size(); ++k) dt.push_back(log.scans[k].time_s - log.scans[k - 1].time_s);
    o.spec.scan_period_s = dt.empty() ? 1.0 : std::max(quantile(dt, 0.5), 1e-3);
    return o;
}

}  // namespace smokescan
