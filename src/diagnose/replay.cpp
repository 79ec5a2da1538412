#include "smokescan/diagnose/replay.hpp"

#include "replay_model.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>

#include <tbb/parallel_for.h>

#include "smokescan/calib/saturation_predict.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/core/order_stats.hpp"
#include "smokescan/fit/omni_fit.hpp"
#include "smokescan/fit/sensor_fit.hpp"
#include "smokescan/sensor_config/laser_kind.hpp"
#include "smokescan/sensor_config/sensor_file.hpp"
#include "smokescan/sensors/beam_model.hpp"

namespace smokescan {
namespace {

/// Half-window of the density's trend (rising or falling) [s]: wider than the smoothing, so that
/// the saturation's noise rarely flips the sign on a plateau.
constexpr double kTrend_s = 3.0;

/// The scene's regional smoke volumes (the camera's calibration is for regional smoke).
std::vector<SmokeVolume> regionalVolumes(const Scene& scene)
{
    std::vector<SmokeVolume> v;
    for (const auto& s : scene.volumes)
        if (s.role == SmokeRole::Regional) v.push_back(s);
    return v;
}

/// The camera's mean density over [t0, t1] (21 samples): the trend's two sides, noise averaged.
double meanDensity(const Replay& r, double t0, double t1)
{
    double sum = 0;
    for (int i = 0; i <= 20; ++i) sum += r.densityAt(t0 + (t1 - t0) * i / 20.0);
    return sum / 21;
}

/// The log's beams must be the sensor's: the same count and angles.
void checkBeams(const RecordedLog& log, const LrfSpec& spec, const std::string& sensor)
{
    const auto& a = log.scans.front().angle_rad;
    if (a.size() != size_t(spec.n_beams))
        throw Error(log.path,
                    fmt("has %zu beams a scan; the scene's sensor '%s' (%s) has %d (a log of another sensor?)",
                        a.size(), sensor.c_str(), sensorTypeName(spec.type), spec.n_beams));
    for (size_t i = 0; i < a.size(); ++i)
        if (std::abs(a[i] - spec.angle(int(i))) > 1e-3)
            throw Error(log.path,
                        fmt("beam %zu is at %.4f rad; the sensor's beam %zu is at %.4f rad (another mounting or "
                            "resolution?)",
                            i, a[i], i, spec.angle(int(i))));
}

/// The recorded ranges must fit the sensor: most of them within its maximum range (else the log's
/// unit is not the one given).
void checkRanges(const Replay& r, const std::string& path)
{
    long long valid = 0, beyond = 0;
    for (const auto& scan : r.range_m)
        for (float v : scan)
            if (!std::isnan(v)) {
                ++valid;
                beyond += v > 1.05 * r.spec.range_max_m;
            }
    if (valid > 0 && beyond > valid / 5)
        throw Error(path,
                    fmt("reads beyond the sensor's %.1f m in %lld of its %lld ranges: is --unit right?",
                        r.spec.range_max_m, beyond, valid));
}

/// The scene's densest regional state as the camera sees it: its field and camera density.
std::pair<SmokeField, double> referenceState(const Scene& scene, const std::vector<SmokeVolume>& regional,
                                             const SaturationPredictor& camera, double step_s)
{
    SmokeField best;
    double best_rho = 0;
    for (double t = scene.t_start_s; t <= scene.t_end_s + 1e-9; t += step_s) {
        SmokeField f = SmokeField::at(regional, t);
        const double rho = camera.density(f);
        if (rho > best_rho) {
            best_rho = rho;
            best = std::move(f);
        }
    }
    if (!(best_rho > 0))
        throw Error(scene.source,
                    "has no regional smoke in the camera's view: nothing to scale to the measured saturation");
    return {std::move(best), best_rho};
}

/// Time blocks (ReplayConfig, kBlockMove): at most block_s long, and shorter where the smoke
/// changes fast — a block also ends once the smoke's density (the camera's, or the traced mean)
/// has moved by kBlockMove of the run's densest since it began (and by more than three of its
/// noise's standard deviations), never under kMinBlock_s. A
/// cause's evidence lies in the smoke's rises and falls, and the held-out test counts blocks: a
/// fixed 3 s put a fast rise into two or three blocks, whose sign flips cannot reach a level
/// however large the gain. The blocks follow the smoke only, never the laser's readings, so the
/// test's null holds as before.
void assignBlocks(Replay& r, double block_s)
{
    double peak = 0;
    for (const ReplayScan& s : r.scans) peak = std::max(peak, s.density);
    int block = 0;
    double t_start = r.scans.front().time_s, rho_start = r.scans.front().density;
    for (ReplayScan& s : r.scans) {
        const double age = s.time_s - t_start;
        // A move beyond the density's own noise (three of its standard deviations) too.
        const double noise = 3 * s.ln_density_sd * s.density;
        const bool moved =
            peak > 0 && std::abs(s.density - rho_start) >= std::max(kBlockMove * peak, noise) && age >= kMinBlock_s;
        if (age >= block_s || moved) {
            ++block;
            t_start = s.time_s;
            rho_start = s.density;
        }
        s.block = block;
    }
}

/// The density a saturation reads as: through the curve, a saturation at or below the curve's
/// floor (the camera's noise in the densest smoke; 0 without one) as the curve's density 1e-4
/// above it — denser than any beam passes, rather than a gap that interpolation would fill low —
/// and one at or above the clear-air value as clear.
double densityOfSaturation(const SaturationCurve& curve, double S)
{
    S = std::max(S, curve.floor + 1e-4);
    return S < curve(0.0) ? curve.invert(S) : 0.0;
}

/// The camera's density series on laser time: each saturation sample, smoothed over smooth_s,
/// through the curve; and the smoothed series' noise. @return the smoothing's half-width in samples.
int densitySeries(const SaturationSeries& raw, const SaturationCurve& curve, double offset_s, double smooth_s,
                  Replay& r)
{
    std::vector<double> dt;
    for (size_t i = 1; i < raw.time_s.size(); ++i) {
        dt.push_back(raw.time_s[i] - raw.time_s[i - 1]);
        if (!(dt.back() > 0))
            throw Error(
                raw.path,
                fmt("time %.6g s follows %.6g s: the camera's times must increase", raw.time_s[i], raw.time_s[i - 1]));
    }
    double s_lo = kInf, s_hi = -kInf;
    for (double v : raw.saturation) s_lo = std::min(s_lo, v), s_hi = std::max(s_hi, v);
    if (raw.saturation.size() < 3 || !(s_hi - s_lo > std::max(0.01, 3 * saturationNoise(raw))))
        throw Error(raw.path,
                    fmt("holds a saturation from %.3g to %.3g: no smoke varies in it beyond its noise, so "
                        "the laser's errors cannot be set against the smoke",
                        s_lo, s_hi));
    const double frame_s = dt.empty() ? 1.0 : std::max(quantile(dt, 0.5), 1e-6);
    r.frame_s = frame_s;
    const int h = int(std::min(std::floor(0.5 * smooth_s / frame_s + 1e-9), double(raw.time_s.size())));
    const SaturationSeries sat = movingAverage(raw, h);
    r.saturation_noise = saturationNoise(raw) / std::sqrt(2.0 * h + 1);
    for (size_t j = 0; j < sat.time_s.size(); ++j) {
        const double rho = densityOfSaturation(curve, sat.saturation[j]);
        r.density_time_s.push_back(sat.time_s[j] - offset_s);
        r.density_series.push_back(rho);
        // Its error through the curve as it is read (the secant over S ± σ_S, the floor
        // included): the tangent claimed 3.5 in ln near the floor where the read was off by 0.2.
        const double S = curve(rho), lo = densityOfSaturation(curve, S + r.saturation_noise),
                     hi = densityOfSaturation(curve, S - r.saturation_noise);
        r.density_ln_sd.push_back(!(rho > 0) ? 0.0 : lo > 0 ? 0.5 * std::log(hi / lo) : std::log(hi / rho));
    }
    if (r.density_time_s.empty())
        throw Error(sat.path, "holds no saturation the calibration curve can read as a density");
    return h;
}

/// The share of one sample's noise σ left between two samples read at weights w and 1 − w:
/// √(w² + (1 − w)² + 2w(1 − w)ρ), ρ = 2h/(2h + 1) the correlation of two neighbouring averages of
/// 2h + 1 samples (1 on a sample, 1/√2 midway between raw ones).
double noiseShare(double w, int h)
{
    const double rho = 2.0 * h / (2.0 * h + 1);
    return std::sqrt(w * w + (1 - w) * (1 - w) + 2 * w * (1 - w) * rho);
}

/// noiseShare at laser time t (1 at or beyond the series' ends).
double interpolatedNoiseShare(const Replay& r, double t, int h)
{
    const auto& ts = r.density_time_s;
    if (ts.size() < 2 || t <= ts.front() || t >= ts.back()) return 1.0;
    const size_t i = size_t(std::upper_bound(ts.begin(), ts.end(), t) - ts.begin()) - 1;
    return noiseShare((t - ts[i]) / (ts[i + 1] - ts[i]), h);
}

/// The physical model's tables (Replay::PhysicalTable): each beam's error probability and
/// noise-free range at the reference state scaled by e^u, over the run's scales and e^3 beyond
/// (room for a shifted threshold and the density's noise), down to e^−5 of the densest.
/// Throws when another thread asked the replay to stop (ReplayConfig::stop).
void checkStop(const std::atomic<bool>* stop)
{
    if (stop && *stop) throw Error("replay", "stopped");
}

/// The tangents d/du of a row of `n` values `y` on a grid of step `du`, for a cubic between the
/// points that is monotone wherever the points are (Fritsch–Carlson: at an interior point the
/// harmonic mean of its two secants when they agree in sign, else 0). At the top 0 (the value
/// stays beyond the grid); at the bottom the slope of the clear-air branch below the grid,
/// clear + (y₀ − clear)·e^(u − u_lo), within what keeps the first piece monotone.
void monotoneTangents(const double* y, size_t n, double du, double clear, double* m)
{
    auto secant = [&](size_t j) { return (y[j + 1] - y[j]) / du; };
    for (size_t j = 1; j + 1 < n; ++j) {
        const double a = secant(j - 1), b = secant(j);
        m[j] = a * b > 0 ? 2 * a * b / (a + b) : 0.0;
    }
    if (n < 2) return;
    const double d0 = secant(0), below = y[0] - clear;
    m[0] = below * d0 > 0 ? std::copysign(std::min(std::abs(below), 3 * std::abs(d0)), d0) : 0.0;
    m[n - 1] = 0.0;
}

void physicalTables(Replay& r, const Scene& scene, const SurfaceSet& surfaces, const SmokeField& ref,
                    const std::vector<Ray>& rays, const std::atomic<bool>* stop)
{
    double s_max = 0;
    for (double d : r.density_series) s_max = std::max(s_max, d / r.density_ref);
    s_max = std::max(s_max, 1e-6);
    Replay::PhysicalTable& t = r.physical;
    // Steps of 1/30 in ln s: fine beside the receiver's onset (a few tenths in ln s wide).
    t.grid = 241;
    t.u_lo = std::log(s_max) - 5.0;
    t.du = 8.0 / double(t.grid - 1);
    const size_t B = r.beams.size(), G = size_t(t.grid);
    for (auto* v : {&t.err, &t.range, &t.sd, &t.err_slope, &t.range_slope, &t.sd_slope}) v->assign(B * G, 0.0);
    for (auto* v : {&t.err_clear, &t.range_clear, &t.sd_clear}) v->assign(B, 0.0);
    SensorConfig plain = r.config;  // the model itself: the extensions are the diagnosis' (Replay::prior)
    plain.extensions = ModelExtensions{};
    const std::unique_ptr<BeamModel> model = makeBeamModel(plain);
    auto evaluate = [&](size_t b, double scale, double& err, double& range, double& sd) {
        const SmokeField f = ref.scaledRegional(scale);
        const BeamWorld w{scene, surfaces, f, false};
        const LaserBeam beam(rays[b], r.beams[b].angle_rad);
        const BeamPrediction p = model->predict(w, beam);
        err = p.p_error;
        range = p.expected.error ? r.beams[b].range_m : double(p.expected.value) * r.spec.unit_m;
        sd = std::min(p.range_sigma_m, r.spec.range_max_m);
    };
    tbb::parallel_for(size_t(0), B, [&](size_t b) {
        checkStop(stop);
        if (r.beams[b].surface < 0) return;
        evaluate(b, 0.0, t.err_clear[b], t.range_clear[b], t.sd_clear[b]);
        for (size_t j = 0; j < G; ++j) {
            const size_t i = b * G + j;
            evaluate(b, std::exp(t.u_lo + t.du * double(j)), t.err[i], t.range[i], t.sd[i]);
        }
        monotoneTangents(t.err.data() + b * G, G, t.du, t.err_clear[b], t.err_slope.data() + b * G);
        monotoneTangents(t.range.data() + b * G, G, t.du, t.range_clear[b], t.range_slope.data() + b * G);
        monotoneTangents(t.sd.data() + b * G, G, t.du, t.sd_clear[b], t.sd_slope.data() + b * G);
    });
    // Where each beam's error table is flat, for the predictive terms' shortcut (finishTerms).
    t.flat_reach.assign(B * G, 0);
    t.flat_reach_clear.assign(B, -1);
    auto reach = [&](const double* row, double lo, double hi, size_t from) {
        size_t k = from;
        while (k + 1 < G && std::max(hi, row[k + 1]) - std::min(lo, row[k + 1]) < 1e-12) {
            ++k;
            lo = std::min(lo, row[k]);
            hi = std::max(hi, row[k]);
        }
        return int(k);
    };
    tbb::parallel_for(size_t(0), B, [&](size_t b) {
        const double* row = t.err.data() + b * G;
        for (size_t j = 0; j < G; ++j) t.flat_reach[b * G + j] = reach(row, row[j], row[j], j);
        const double c = t.err_clear[b];
        if (std::max(c, row[0]) - std::min(c, row[0]) < 1e-12)
            t.flat_reach_clear[b] = reach(row, std::min(c, row[0]), std::max(c, row[0]), 0);
    });
}

/// The scene's own columns at each scan (SmokeShape::Timeline: every scan, split into the
/// volumes the camera sees, with its density there, and the rest) and how far the reference
/// shape misstates them (Replay::shape_error_ln, on every scan or, for the reference shape, up to
/// 100 scans spread over the run).
void traceShapes(Replay& r, const std::vector<SmokeVolume>& regional, const SaturationPredictor& camera,
                 const std::vector<Ray>& rays, const BeamQuery& q, SmokeShape shape, const std::atomic<bool>* stop)
{
    r.shape = shape;
    r.shape_floor = 0.01 * r.density_ref;
    const bool timeline = shape == SmokeShape::Timeline;
    const size_t n = r.scans.size(), B = rays.size(), sampled = std::max<size_t>(1, (n + 99) / 100);
    const size_t stride = timeline ? 1 : sampled;
    // A volume the camera sees at any sampled scan is scaled by it; the rest is the scene's.
    std::vector<SmokeVolume> seen, unseen;
    for (const SmokeVolume& v : regional) {
        double most = 0;
        for (size_t k = 0; k < n; k += sampled)
            most = std::max(most, camera.density(SmokeField::at({v}, r.scans[k].time_s)));
        (most > 1e-3 * r.density_ref ? seen : unseen).push_back(v);
    }
    auto columns = [&](const std::vector<SmokeVolume>& volumes, double t) {
        checkStop(stop);
        std::vector<float> col(B, 0.0f);
        if (volumes.empty()) return col;
        const SmokeField f = SmokeField::at(volumes, t);
        tbb::parallel_for(size_t(0), B, [&](size_t b) {
            col[b] = float(f.trace(rays[b], 0.0, r.beams[b].sight_m, q).column_regional);
        });
        return col;
    };
    if (timeline) r.column.assign(n, {}), r.column_unseen.assign(n, {});
    const double P = r.config.paper.penetration_power, c = P / 20;
    double ss = 0;
    long long count = 0;
    for (size_t k = 0; k < n; k += stride) {
        const double t = r.scans[k].time_s;
        const double scene_rho = camera.density(SmokeField::at(regional, t));
        std::vector<float> col = columns(seen, t), rest = columns(unseen, t);
        for (size_t b = 0; b < B; ++b) {
            const double frozen = scene_rho / r.density_ref * r.beams[b].column_ref, own = double(col[b] + rest[b]);
            if (std::max(frozen, own) < P / 5) continue;
            ss += std::pow(std::log((frozen + c) / (own + c)), 2);
            ++count;
        }
        if (timeline) {
            r.scans[k].scene_density = seen.empty() ? 0.0 : camera.density(SmokeField::at(seen, t));
            r.column[k] = std::move(col);
            r.column_unseen[k] = std::move(rest);
        }
    }
    r.shape_error_ln = count ? std::sqrt(ss / double(count)) : 0.0;
}

/// The checks every replay makes before any work.
void checkReplay(const FitInputs& in, const SensorConfig& config, const ReplayConfig& cfg)
{
    if (!in.scene) throw Error("diagnose", "needs --scene (the geometry the run is replayed in)");
    if (!(cfg.block_s >= 0.1)) throw Error("--block", "must be at least 0.1 s");
    if ((in.log.scans.back().time_s - in.log.scans.front().time_s) / cfg.block_s > 1e5)
        throw Error("--block", "would split the run into more than 100000 blocks");
    if (config.model == SensorModel::Physical && !laserKind(config.type).fitsPhysicalModel())
        throw Error("--model",
                    "the physical model is replayed for the urg04lx only (the lms200's error probability "
                    "is a Monte Carlo estimate, too slow per beam and scale)");
    if (config.model == SensorModel::Physical && in.saturation.time_s.empty())
        throw Error("--model", "the physical model is replayed from a saturation series only (give --saturation)");
    if (config.model == SensorModel::Physical && cfg.shape == SmokeShape::Timeline)
        throw Error("--smoke-shape",
                    "timeline is replayed with the paper model only (the physical model's tables are the reference "
                    "state's, scaled)");
}

/// A log's reading as the replay keeps it: scan k, beam b, the value in metres → a range [m], or
/// NaN for the sensor's "no return".
using RecordedValue = std::function<float(size_t k, size_t b, double m)>;

/// The replay's smoke and scans, once its beams (r.beams, their rays) are known.
Replay replayScans(const FitInputs& in, Replay r, const std::vector<Ray>& rays, const ReplayConfig& cfg,
                   const RecordedValue& recorded)
{
    const Scene& scene = *in.scene;
    const std::vector<SmokeVolume> regional = regionalVolumes(scene);
    BeamQuery q;
    q.wavelength_nm = r.spec.wavelength_nm;
    r.from_saturation = !in.saturation.time_s.empty();
    double t0 = in.log.scans.front().time_s, t1 = in.log.scans.back().time_s;
    std::optional<SaturationPredictor> camera;
    if (r.from_saturation) {
        camera.emplace(scene, *in.surfaces, in.calibration.curve, cfg.camera, cfg.target_prefix);
        const auto [ref, rho_ref] = referenceState(scene, regional, *camera, cfg.time_step_s);
        r.density_ref = rho_ref;
        for (size_t b = 0; b < r.beams.size(); ++b)
            r.beams[b].column_ref = ref.trace(rays[b], 0.0, r.beams[b].sight_m, q).column_regional;
        r.curve = in.calibration.curve;
        r.smooth_h = densitySeries(in.saturation, in.calibration.curve, cfg.offset_s, cfg.smooth_s, r);
        if (r.isPhysical()) physicalTables(r, scene, *in.surfaces, ref, rays, cfg.stop);
        const double c0 = r.density_time_s.front(), c1 = r.density_time_s.back();
        if (t1 < c0 || t0 > c1)
            throw Error(in.saturation.path,
                        fmt("does not overlap the laser log: laser %.1f-%.1f s, camera %.1f-%.1f s on the "
                            "laser's clock (offset %.2f s); give --offset",
                            t0, t1, c0, c1, cfg.offset_s));
        // Scans the camera did not see have no measured smoke: they are left out.
        t0 = std::max(t0, c0);
        t1 = std::min(t1, c1);
    }
    // A scan farther than this from the camera's nearest sample has no measured smoke either.
    const double max_gap_s = std::max(2.0, 10 * r.frame_s);
    auto nearSample = [&](double t) {
        const auto& ts = r.density_time_s;
        const auto it = std::lower_bound(ts.begin(), ts.end(), t);
        double d = kInf;
        if (it != ts.end()) d = *it - t;
        if (it != ts.begin()) d = std::min(d, t - *(it - 1));
        return d <= max_gap_s;
    };
    if (!r.from_saturation && (t1 < scene.t_start_s || t0 > scene.t_end_s))
        throw Error(in.log.path,
                    fmt("spans %.1f-%.1f s, outside the scene's time line (%.1f-%.1f s); give the "
                        "camera's --saturation",
                        t0, t1, scene.t_start_s, scene.t_end_s));
    for (const LaserLogScan& s : in.log.scans) {
        if (s.time_s < t0 || s.time_s > t1) continue;
        if (r.from_saturation && !nearSample(s.time_s)) continue;
        ReplayScan sc;
        sc.time_s = s.time_s;
        std::vector<float> rec(s.range.size());
        const size_t k = size_t(&s - in.log.scans.data());
        for (size_t b = 0; b < s.range.size(); ++b) rec[b] = recorded(k, b, s.range[b] * in.log.unit_m);
        r.range_m.push_back(std::move(rec));
        if (r.from_saturation) {
            sc.density = r.densityAt(s.time_s);
            sc.saturation = in.calibration.curve(sc.density);
            sc.ln_density_sd = r.lnDensitySdAt(s.time_s);
            const auto [lo, hi] = r.densityBandAt(s.time_s);
            const double noise_S = r.saturation_noise * interpolatedNoiseShare(r, s.time_s, r.smooth_h);
            // Rising: the next 3 s's mean density exceeds the last 3 s's by more than twice the
            // difference's noise (each mean averages about kTrend_s / frame_s camera samples); on a
            // plateau the smoke is steady, as the scan's own time lines say (regionalSmokeRising).
            const double noise = 0.5 * (hi - lo) * r.saturation_noise / std::max(noise_S, 1e-300);
            const double trend_sd = noise * std::sqrt(2.0 * r.frame_s / kTrend_s);
            sc.rising = meanDensity(r, s.time_s, s.time_s + kTrend_s) - meanDensity(r, s.time_s - kTrend_s, s.time_s) >
                2 * trend_sd;
        } else {
            checkStop(cfg.stop);
            const SmokeField now = SmokeField::at(regional, s.time_s);
            std::vector<float> col(rays.size());
            double now_sum = 0;
            for (size_t b = 0; b < rays.size(); ++b) {
                col[b] = float(now.trace(rays[b], 0.0, r.beams[b].sight_m, q).column_regional);
                now_sum += col[b];
            }
            sc.density = now_sum / double(rays.size());
            sc.rising = regionalSmokeRising(scene, s.time_s);  // as `scan` simulates a hysteresis
            r.column.push_back(std::move(col));
        }
        r.scans.push_back(sc);
    }
    if (r.scans.empty()) throw Error(in.log.path, "has no scan the camera's saturation covers");
    if (r.from_saturation)
        traceShapes(r, regional, *camera, rays, q, cfg.shape, cfg.stop);
    else
        r.shape = SmokeShape::Timeline;  // the scene's own time line, traced
    assignBlocks(r, cfg.block_s);
    checkRanges(r, in.log.path);
    return r;
}

/// The sensor file's extensions as the model diagnosed, with the clock offset the replay
/// assumes. @throw Error for a surface the scene lacks.
ModelExtensions priorOf(const Replay& r, const ModelExtensions& e)
{
    ModelExtensions m = e;
    m.clock_offset_s = r.offset_s;
    (void)detail::ReplayModel(r, m);  // refuses a surface the scene does not have
    return m;
}

}  // namespace

namespace {
constexpr std::pair<SmokeShape, const char*> kShapes[] = {{SmokeShape::Reference, "reference"},
                                                          {SmokeShape::Timeline, "timeline"}};
}  // namespace

std::pair<double, double> Replay::densityBandAt(double t) const
{
    const double noise = saturation_noise * interpolatedNoiseShare(*this, t, smooth_h), S = curve(densityAt(t));
    return {densityOfSaturation(curve, S + noise), densityOfSaturation(curve, S - noise)};
}

double Replay::lnDensitySdAt(double t) const
{
    const auto& ts = density_time_s;
    if (ts.empty()) return 0.0;
    if (ts.size() == 1 || t <= ts.front()) return density_ln_sd.front();
    if (t >= ts.back()) return density_ln_sd.back();
    const size_t i = size_t(std::upper_bound(ts.begin(), ts.end(), t) - ts.begin()) - 1;
    const double w = (t - ts[i]) / (ts[i + 1] - ts[i]);
    return ((1 - w) * density_ln_sd[i] + w * density_ln_sd[i + 1]) * noiseShare(w, smooth_h);
}

const char* smokeShapeName(SmokeShape s)
{
    for (const auto& [shape, name] : kShapes)
        if (shape == s) return name;
    return "?";
}

SmokeShape smokeShapeOf(const std::string& name, const std::string& key)
{
    for (const auto& [shape, n] : kShapes)
        if (name == n) return shape;
    throw Error(key, "'" + name + "' is not a smoke shape (reference, timeline)");
}

Replay replayRun(const FitInputs& in, const SensorConfig& config, const ReplayConfig& cfg)
{
    checkReplay(in, config, cfg);
    Replay r;
    r.spec = specFor(config);
    r.config = config;
    r.offset_s = cfg.offset_s;
    checkBeams(in.log, r.spec, in.mount.name);
    for (const auto& s : in.scene->surfaces) r.surface_names.push_back(s.name);
    r.prior = priorOf(r, config.extensions);
    // Beams: what each one hits.
    std::vector<Ray> rays;
    for (int i = 0; i < r.spec.n_beams; ++i) {
        rays.push_back(in.mount.beamRay(r.spec.angle(i)));
        const SurfaceHit h = in.surfaces->closest(rays.back(), r.spec.range_max_m);
        ReplayBeam b;
        b.surface = h.surface;
        b.range_m = b.sight_m = h.endOr(r.spec.range_max_m);
        b.angle_rad = r.spec.angle(i);
        b.incidence_rad = h.hit ? std::acos(std::min(1.0, std::abs(rays.back().d.dot(h.normal)))) : 0.0;
        r.beams.push_back(b);
    }
    const LrfSpec spec = r.spec;
    return replayScans(in, std::move(r), rays, cfg,
                       [&spec](size_t, size_t, double m) { return spec.isErrorRange(m) ? NAN : float(m); });
}

Replay replayOmniRun(const OmniFitInputs& o, const OmniSensorFile& file, const ReplayConfig& cfg)
{
    SensorConfig config;  // the paper model at the omnicam's onset; no laser of its own
    config.model = SensorModel::Paper;
    config.paper.penetration_power = file.penetration_power;
    config.extensions = file.extensions;
    config.sensor_file = file.path;
    checkReplay(o.in, config, cfg);
    Replay r;
    r.spec = o.spec;
    r.config = config;
    r.offset_s = cfg.offset_s;
    const Scene& scene = *o.in.scene;
    for (const auto& s : scene.surfaces) r.surface_names.push_back(s.name);
    r.prior = priorOf(r, config.extensions);
    const std::vector<double>& angle = o.in.log.scans.front().angle_rad;
    double unwrapped = angle.front();  // bearings on from the first: a sector may span ±180°
    for (size_t i = 0; i < angle.size(); ++i) {
        if (i > 0) unwrapped += std::remainder(angle[i] - angle[i - 1], 2 * M_PI);
        ReplayBeam b;
        const bool seen = o.truth_m[i] < r.spec.range_max_m;
        b.surface = seen ? o.surface[i] : -1;  // beyond the maximum range: left out, as a laser's no return
        b.range_m = std::min(o.truth_m[i], r.spec.range_max_m);
        b.angle_rad = unwrapped;
        b.sight_m = o.sight_m[i];
        b.sigma_m = o.pixel_m[i];
        r.beams.push_back(b);
    }
    const size_t n = angle.size();
    return replayScans(o.in, std::move(r), o.sight, cfg, [&o, n](size_t k, size_t b, double m) {
        return o.outcome[k * n + b] == ReadingOutcome::Long ? NAN : float(m);
    });
}

}  // namespace smokescan
