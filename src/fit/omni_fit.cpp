#include "smokescan/fit/omni_fit.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/core/order_stats.hpp"
#include "smokescan/media/smoke.hpp"
#include "smokescan/omni/scanline_truth.hpp"

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
    if (!(c.tolerance_m < 0.5 * c.max_range_m))
        throw Error("--tolerance", fmt("must be below half the maximum range (half of %g m)", c.max_range_m));
}

/// The mean step between a log's bearings, unwrapped [rad] (its sign: their sense of turning).
double meanStep(const std::vector<double>& a)
{
    double sum = 0;
    for (size_t i = 1; i < a.size(); ++i) sum += std::remainder(a[i] - a[i - 1], 2 * M_PI);
    return a.size() > 1 ? sum / double(a.size() - 1) : 0.0;
}

/// Whether n bearings `step` apart go once round the circle (the first and the last neighbours).
bool allRound(size_t n, double step)
{
    return n > 2 && std::abs(double(n) * std::abs(step) - 2 * M_PI) < 0.5 * std::abs(step);
}

/// The omnirange layout: scanlines evenly spaced all round (a laser's log is not).
void checkLayout(const RecordedLog& log)
{
    const std::vector<double>& a = log.scans.front().angle_rad;
    const size_t n = a.size();
    const double step = meanStep(a);
    bool even = n >= 8 && std::abs(step) > 0;
    for (size_t i = 1; even && i < n; ++i)
        even = std::abs(std::remainder(a[i] - a[i - 1], 2 * M_PI) - step) < std::min(1e-3, 0.25 * std::abs(step));
    if (!even || !allRound(n, step))
        throw Error(log.path,
                    fmt("has %zu bearings that are not evenly spaced all round, as omnirange writes them "
                        "(a laser's log? give its --sensor-type)",
                        n));
}

/// Most readings beyond the maximum range, or below 2 cm: the log's unit is not the one given.
void checkUnit(const RecordedLog& log, double max_range_m)
{
    long long n = 0, beyond = 0, tiny = 0;
    for (const LaserLogScan& s : log.scans)
        for (double v : s.range) {
            ++n;
            beyond += v * log.unit_m > 1.05 * max_range_m;
            tiny += v * log.unit_m < 0.02;
        }
    if (beyond > n / 5 || tiny > n / 5)
        throw Error(log.path,
                    fmt("reads %s in %lld of its %lld readings: is --unit (or --max-range) right?",
                        beyond > n / 5 ? fmt("beyond the omnicam's %.1f m", max_range_m).c_str() : "below 2 cm",
                        std::max(beyond, tiny), n));
}

/// The floor the height puts below the camera must be the scene's, where the scene has one there.
void checkFloor(const SurfaceSet& surfaces, const Pose& eye, double height_m, const std::string& camera)
{
    if (height_m > 100)
        throw Error("--floor-z", fmt("puts the floor %.0f m below the omni camera (at most 100)", height_m));
    const SurfaceHit h = surfaces.closest(Ray{eye.t, Vec3(0, 0, -1)}, 2 * height_m + 1);
    if (h.hit && std::abs(h.t_m - height_m) > 0.05)
        throw Error("--floor-z",
                    fmt("puts the floor %.3f m below the omni camera '%s', but the scene's surface "
                        "straight below it is %.3f m down",
                        height_m, camera.c_str(), h.t_m));
}

/// In clear air the omnicam reads its truth on most scanlines (the built-in maze, the hardest, on
/// 84 %). Its clearest scans (the highest tenth of the camera's saturation at their times; without
/// a saturation series, its best scan) reading wrong on more than a quarter of them: a log of
/// another scene, camera, pose or floor, or one without clear air, which has no onset to fit.
void checkAgreement(const OmniFitInputs& o, const std::string& path, double tolerance_m)
{
    const RecordedLog& log = o.in.log;
    std::vector<double> share, sat;
    for (size_t k = 0; k < o.failed.size(); ++k) {
        size_t bad = 0;
        for (bool b : o.failed[k]) bad += b;
        share.push_back(double(bad) / double(std::max<size_t>(1, o.failed[k].size())));
        sat.push_back(o.in.saturation.time_s.empty() ? NAN : saturationAt(o.in.saturation, log.scans[k].time_s));
    }
    double clear_sat = NAN, worst = 0;
    std::vector<double> seen;
    for (double v : sat)
        if (std::isfinite(v)) seen.push_back(v);
    if (!seen.empty()) {
        clear_sat = quantile(seen, 0.9);
        double sum = 0;
        int n = 0;
        for (size_t k = 0; k < share.size(); ++k)
            if (std::isfinite(sat[k]) && sat[k] >= clear_sat) sum += share[k], ++n;
        worst = sum / std::max(1, n);
    } else {
        worst = *std::min_element(share.begin(), share.end());
    }
    if (worst > 0.25)
        throw Error(path,
                    fmt("reads more than %g m off the truth on %.0f %% of its scanlines in its clearest scans%s: is it "
                        "the omnicam's log of this scene, camera ('%s') and floor, in --unit, with clear air in it?",
                        tolerance_m, 100 * worst,
                        std::isfinite(clear_sat) ? fmt(" (saturation at least %.3f)", clear_sat).c_str() : "",
                        o.camera.c_str()));
}

/// A bearing interval on the log's circle (−π, π]: shifted there, and split where it crosses ±π.
void addWrapped(std::vector<std::pair<double, double>>& out, double a0, double a1)
{
    if (a1 - a0 >= 2 * M_PI) {
        out.emplace_back(-M_PI, M_PI);
        return;
    }
    const double shift = a0 - std::remainder(a0, 2 * M_PI);
    a0 -= shift;
    a1 -= shift;
    // A bearing written just past ±π (omnirange's 180° is 3.141593) counts on either side.
    constexpr double kSeam = 1e-5;
    if (a1 <= M_PI) {
        out.emplace_back(a0 <= -M_PI + kSeam ? a0 - kSeam : a0, a1 >= M_PI - kSeam ? a1 + kSeam : a1);
        return;
    }
    out.emplace_back(a0, M_PI + kSeam);
    out.emplace_back(-M_PI - kSeam, a1 - 2 * M_PI);
}

/// Groups from the truth: per surface named prefix*, the scanlines within the maximum range whose
/// neighbours see the same surface, each an interval of its own bearing.
std::vector<BeamGroup> truthGroups(const Scene& scene, const OmniFitInputs& o, const std::vector<double>& angle,
                                   const std::string& prefix, double max_range_m, double tolerance_m)
{
    std::vector<BeamGroup> out;
    std::map<int, size_t> index;
    const size_t n = angle.size();
    // Scanlines all round (omnirange's): the first and the last are neighbours.
    const bool ring = allRound(n, meanStep(angle));
    for (size_t i = 0; i < n; ++i) {
        const int s = o.surface[i];
        if (s < 0 || !(o.truth_m[i] < max_range_m - tolerance_m)) continue;
        if (scene.surfaces[size_t(s)].name.rfind(prefix, 0) != 0) continue;
        const bool first = i == 0, last = i + 1 == n;
        if (!ring && (first || last)) continue;
        if (o.surface[first ? n - 1 : i - 1] != s || o.surface[last ? 0 : i + 1] != s) continue;
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
    for (BeamGroup& g : groups) {
        if (g.range_m > 0)
            throw Error(
                cfg.surfaces.empty() ? cfg.surfaces_file : std::string("--surface"),
                "group '" + g.name + "' gives a range: the omnicam's distances and lines of sight come from the scene");
        std::vector<std::pair<double, double>> wrapped;  // bearings on the log's circle
        for (const auto& [a0, a1] : g.intervals_rad) addWrapped(wrapped, a0, a1);
        g.intervals_rad = wrapped;
    }
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
    checkLayout(log);
    checkUnit(log, omni.max_range_m);
    const Camera& cam = standingCamera(scene, log, omni.camera);
    o.camera = cam.name;
    const Pose pose = scene.cameraAt(cam, log.scans.front().time_s).pose;
    o.height_m = pose.t.z() - omni.floor_z_m;
    if (!(o.height_m > 0))
        throw Error("--floor-z",
                    fmt("puts the floor at or above the omni camera '%s' (at %.3f m)", cam.name.c_str(), pose.t.z()));
    checkFloor(*o.in.surfaces, pose, o.height_m, cam.name);
    // The truth is the geometry's: smoke does not move an obstacle.
    const std::vector<double>& angle = log.scans.front().angle_rad;
    const ScanlineTruth truth = scanlineTruth(*o.in.surfaces, SmokeField{}, pose, o.height_m, angle, omni.max_range_m);
    o.truth_m = truth.range_m;
    o.surface = truth.surface;
    o.sight = truth.sight;
    o.sight_m = truth.sight_m;
    // One pixel at radius ρ is dθ = (1 + cos θ)/R of incidence, and d = h·tan θ moves by h·sec²θ·dθ.
    const double R = cam.mirror_radius_px, h = o.height_m;
    for (double sight : o.sight_m) o.pixel_m.push_back(sight * sight / h * (1 + h / sight) / R);
    for (const LaserLogScan& s : log.scans) {
        std::vector<bool> f(s.range.size());
        for (size_t i = 0; i < f.size(); ++i) {
            const ReadingOutcome c =
                classifyReading(s.range[i] * log.unit_m, o.truth_m[i], omni.max_range_m, omni.tolerance_m);
            f[i] = c != ReadingOutcome::Ok;
            o.outcome.push_back(c);
            o.shorter += c == ReadingOutcome::Short;
            o.longer += c == ReadingOutcome::Long;
        }
        o.readings += (long long)f.size();
        o.failed.push_back(std::move(f));
    }
    checkAgreement(o, log.path, omni.tolerance_m);
    if (!omni.groups)
        o.in.groups.clear();
    else if (cfg.surfaces.empty() && cfg.surfaces_file.empty())
        o.in.groups = truthGroups(scene, o, angle, cfg.prefix, omni.max_range_m, omni.tolerance_m);
    else
        o.in.groups = userGroups(cfg, o.in.sources);
    if (o.in.sources.groups_from.empty()) o.in.sources.groups_from = scene.source;
    for (BeamGroup& g : o.in.groups) {
        std::vector<double> sight;
        for (size_t i = 0; i < angle.size(); ++i)
            if (g.contains(angle[i])) sight.push_back(o.sight_m[i]);
        if (!sight.empty()) g.range_m = median(std::move(sight));
    }
    o.spec.n_beams = int(angle.size());
    o.spec.angle0_rad = angle.front();
    o.spec.dangle_rad = meanStep(angle);
    o.spec.range_min_m = 0;
    o.spec.range_max_m = omni.max_range_m;
    o.spec.unit_m = log.unit_m;
    o.spec.wavelength_nm = 550;  // the camera's: visible light
    std::vector<double> dt;
    for (size_t k = 1; k < log.scans.size(); ++k) dt.push_back(log.scans[k].time_s - log.scans[k - 1].time_s);
    o.spec.scan_period_s = dt.empty() ? 1.0 : std::max(quantile(dt, 0.5), 1e-3);
    return o;
}

}  // namespace smokescan
