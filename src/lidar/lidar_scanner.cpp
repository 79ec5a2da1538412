#include "smokescan/lidar/lidar_scanner.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "smokescan/core/error.hpp"
#include "smokescan/core/random.hpp"
#include "smokescan/lidar/waveform_peaks.hpp"

namespace smokescan {
namespace {

/// The source that sent most of the power within an echo's span (the pulse's reach around it).
EchoSource dominantSource(const BeamSignal& s, const WaveformEcho& e, double reach_m)
{
    double power[3] = {0, 0, 0};
    const double a = e.lead_m - reach_m, b = e.trail_m + reach_m;
    for (const Echo& x : s.echoes)
        if (x.range_m >= a && x.range_m <= b) power[int(x.source)] += x.power;
    if (!s.smoke_cells.empty()) {
        const size_t k0 = size_t(std::max(0.0, std::ceil(a / s.smoke_cell_m)));
        const size_t k1 = std::min(s.smoke_cells.size(), size_t(std::max(0.0, std::floor(b / s.smoke_cell_m)) + 1));
        for (size_t k = k0; k < k1; ++k) power[int(EchoSource::Smoke)] += s.smoke_cells[k];
    }
    return EchoSource(int(std::max_element(power, power + 3) - power));
}

/// The source of a peak that rose `height` out of another's run: a surface or mirror when their
/// echoes within its span (the pulse's reach around it) sent at least half of that rise, else the
/// smoke (a denser stretch of it).
EchoSource risingSource(const BeamSignal& s, const WaveformEcho& e, double reach_m, double height)
{
    double power[3] = {0, 0, 0};
    for (const Echo& x : s.echoes)
        if (x.range_m >= e.lead_m - reach_m && x.range_m <= e.trail_m + reach_m) power[int(x.source)] += x.power;
    const double surface = power[int(EchoSource::Surface)], mirror = power[int(EchoSource::Mirror)];
    if (surface + mirror < 0.5 * height) return EchoSource::Smoke;
    return surface >= mirror ? EchoSource::Surface : EchoSource::Mirror;
}

/// The echo's height above `pedestal` from the log-parabola through its largest sample and their
/// neighbours less the pedestal (exact for a lone Gaussian pulse on a flat pedestal); the largest
/// sample's when one of them is not above the pedestal.
double refinedPeak(const Waveform& f, const WaveformEcho& e, double pedestal, double* noise = nullptr)
{
    if (noise) *noise = 1;  // the sample's own, where the parabola is not used
    const long k = std::lround((e.peak_m - f.lo) / f.dr);
    if (k < 1 || size_t(k + 1) >= f.w.size()) return e.peak - pedestal;
    const double a = f.w[size_t(k - 1)] - pedestal, b = f.w[size_t(k)] - pedestal, c = f.w[size_t(k + 1)] - pedestal;
    if (!(a > 0 && b > 0 && c > 0)) return e.peak - pedestal;
    const double la = std::log(a), lb = std::log(b), lc = std::log(c), curv = la - 2 * lb + lc;
    if (!(curv < 0)) return e.peak - pedestal;
    const double delta = 0.5 * (la - lc) / curv;
    const double peak = std::exp(lb - 0.25 * (la - lc) * delta);
    if (noise) {
        // ln peak = lb − D²/(8C), D = la − lc, C = curv: each sample's noise through its log.
        const double D = la - lc, q = D * D / (8 * curv * curv);
        const double ga = (-D / (4 * curv) + q) / a, gb = (1 - 2 * q) / b, gc = (D / (4 * curv) + q) / c;
        *noise = peak * std::sqrt(ga * ga + gb * gb + gc * gc);
    }
    return peak;
}

/// Where the echo's leading edge crosses half its height above `pedestal`: on the log-parabola
/// through the samples around the crossing less the pedestal (exact for a lone Gaussian pulse on a
/// flat pedestal); the linear crossing when one of them is not above the pedestal or the parabola
/// does not cross there.
double refinedLead(const Waveform& f, const WaveformEcho& e, double height, double pedestal)
{
    const long j = long(std::ceil((e.lead_m - f.lo) / f.dr));
    if (j < 1 || size_t(j + 1) >= f.w.size()) return e.lead_m;
    const double y0 = f.w[size_t(j - 1)] - pedestal, y1 = f.w[size_t(j)] - pedestal, y2 = f.w[size_t(j + 1)] - pedestal;
    if (!(y0 > 0 && y1 > 0 && y2 > 0)) return e.lead_m;
    const double A = std::log(y1) - std::log(0.5 * height), B = 0.5 * (std::log(y2) - std::log(y0)),
                 C = 0.5 * (std::log(y2) + std::log(y0)) - std::log(y1);
    // A + B·t + C·t² = 0 for t in [−1, 1] (t in samples from j), the root nearest the linear one.
    const double t_lin = (e.lead_m - f.lo) / f.dr - double(j);
    double t = NAN;
    if (std::abs(C) < 1e-12) {
        if (B != 0) t = -A / B;
    } else {
        const double disc = B * B - 4 * C * A;
        if (disc >= 0) {
            const double r1 = (-B + std::sqrt(disc)) / (2 * C), r2 = (-B - std::sqrt(disc)) / (2 * C);
            t = std::abs(r1 - t_lin) < std::abs(r2 - t_lin) ? r1 : r2;
        }
    }
    if (!(t >= -1 && t <= 1)) return e.lead_m;
    return f.lo + (double(j) + t) * f.dr;
}

/// Keys the extensions' dropout draws apart from the receiver's noise.
constexpr uint64_t kDropoutKey = 0x64726f706f7574ULL;

/// The echoes of the waveform `f` (the receiver's noise added to it in place when rng is given)
/// into `out`, whose storage is reused.
void receiveEchoesIn(const LidarSpec& spec, const BeamSignal& s, Waveform& f, KeyedRng* rng,
                     std::vector<LidarEcho>& out);

/// selectReturns into `out` (at most two): how many.
int selectReturnsInto(const std::vector<LidarEcho>& e, ReturnMode mode, bool dual_second_strongest, size_t out[2]);

/// receiveEchoes into `out`, whose storage is reused.
void receiveEchoesInto(const LidarSpec& spec, const BeamSignal& s, KeyedRng* rng, std::vector<LidarEcho>& out)
{
    // Two samples per pulse σ: the peak and the leading edge each from a log-parabola through the
    // samples around them, exact for a lone Gaussian pulse.
    thread_local Waveform f;  // storage kept for the thread's next beam
    pulsedWaveform(spec.range_max_m, spec.receiver, s, 2, f);
    receiveEchoesIn(spec, s, f, rng, out);
}

}  // namespace

std::vector<LidarEcho> receiveEchoes(const LidarSpec& spec, const BeamSignal& s, KeyedRng* rng)
{
    std::vector<LidarEcho> out;
    receiveEchoesInto(spec, s, rng, out);
    return out;
}

std::vector<LidarEcho> receiveEchoes(const LidarSpec& spec, const BeamSignal& s, Waveform f, KeyedRng* rng)
{
    std::vector<LidarEcho> out;
    receiveEchoesIn(spec, s, f, rng, out);
    return out;
}

namespace {

void receiveEchoesIn(const LidarSpec& spec, const BeamSignal& s, Waveform& f, KeyedRng* rng,
                     std::vector<LidarEcho>& out)
{
    const PhysicalParams& p = spec.receiver;
    out.clear();
    if (f.w.empty()) return;
    if (rng)
        for (double& w : f.w) w += p.noise_floor * rng->normalZiggurat();
    const double fwhm = 2.354820045 * f.sig_p, threshold = p.threshold_snr * p.noise_floor;
    // A peak must rise out of the signal before it by as much as an echo must rise out of the
    // noise, and by one noise sd at least (a receiver asked for its faint echoes at a threshold
    // of 0 would otherwise split its runs at every pair of equal samples).
    thread_local std::vector<WaveformPeak> peaks;  // storage kept for the thread's next beam
    waveformPeaks(f, threshold, std::max(threshold, p.noise_floor), peaks);
    for (const WaveformPeak& w : peaks) {
        const WaveformEcho& e = w.echo;
        // A run whose leading edge the waveform does not hold (nearer than half the pulse's
        // length) has no measurable range: the blind zone every pulsed lidar has. Its first peak
        // is not an echo; a peak that rises out of it later is (a wall behind the near smoke).
        if (w.opens_run && f.lo <= 0 && e.lead_m <= f.lo) continue;
        LidarEcho x;
        x.peak = refinedPeak(f, e, w.pedestal, rng ? nullptr : &x.peak_noise);
        if (w.pedestal > 0) x.peak_noise = std::hypot(x.peak_noise, 1.0);  // the valley's own sample
        x.pedestal = w.pedestal;
        x.standout = w.opens_run ? x.peak : std::min(x.peak, w.fall);
        x.range_m = refinedLead(f, e, x.peak, w.pedestal) + 0.5 * fwhm +
            (rng ? spec.range_sigma_m * rng->normalZiggurat() : 0.0);
        if (!(x.range_m >= spec.range_min_m && x.range_m <= spec.range_max_m)) continue;
        x.intensity = std::min(255.0, 100 * x.peak * x.range_m * x.range_m / std::max(1e-9, p.overlap(x.range_m)));
        x.source = w.opens_run ? dominantSource(s, e, 2 * f.sig_p) : risingSource(s, e, 2 * f.sig_p, x.peak);
        out.push_back(x);
        if (int(out.size()) == spec.max_echoes) break;
    }
}

}  // namespace

namespace {

int selectReturnsInto(const std::vector<LidarEcho>& e, ReturnMode mode, bool dual_second_strongest, size_t out[2])
{
    if (e.empty()) return 0;
    auto strongestBut = [&](size_t skip) {
        size_t best = e.size();
        for (size_t i = 0; i < e.size(); ++i)
            if (i != skip && (best == e.size() || e[i].peak > e[best].peak)) best = i;
        return best;
    };
    const size_t strongest = strongestBut(e.size()), last = e.size() - 1;
    auto one = [&](size_t a) {
        out[0] = a;
        return 1;
    };
    switch (mode) {
    case ReturnMode::First:
        return one(0);
    case ReturnMode::Last:
        return one(last);
    case ReturnMode::Strongest:
        return one(strongest);
    case ReturnMode::Dual: {
        // Strongest and last: when the strongest is the last, Velodyne gives the second strongest.
        const size_t other = dual_second_strongest || strongest == last ? strongestBut(strongest) : last;
        if (other == e.size()) return one(strongest);
        out[0] = std::min(strongest, other);
        out[1] = std::max(strongest, other);
        return 2;
    }
    }
    return 0;
}

}  // namespace

std::vector<size_t> selectReturns(const std::vector<LidarEcho>& e, ReturnMode mode, bool dual_second_strongest)
{
    size_t kept[2];
    const int n = selectReturnsInto(e, mode, dual_second_strongest, kept);
    return std::vector<size_t>(kept, kept + n);
}

SensorMount defaultLidarMount(const Scene& scene, const std::string& name)
{
    SensorMount mount;
    mount.name = name;
    if (scene.sensors.empty()) return mount;
    const SensorMount& first = scene.sensors.front();
    const LrfSpec laser = specFor(first.config);
    const double ahead = laser.angle0_rad + 0.5 * laser.dangle_rad * (laser.n_beams - 1);
    mount.pose = first.pose;
    mount.pose.R = first.pose.R * Eigen::AngleAxisd(ahead, Vec3::UnitZ()).toRotationMatrix();
    mount.robot = first.robot;
    return mount;
}

LidarScanner::LidarScanner(const Scene& scene, const SurfaceSet& surfaces, const SensorMount& mount, LidarSpec spec,
                           ReturnMode mode, uint64_t seed)
    : scene_(scene), surfaces_(surfaces), mount_(mount), spec_(std::move(spec)), mode_(mode), seed_(seed)
{
    if (!spec_.offers(mode)) {
        std::string modes;
        for (ReturnMode m : spec_.return_modes) modes += (modes.empty() ? "" : ", ") + std::string(returnModeName(m));
        throw Error("--returns", "the " + spec_.name + " offers " + modes + ", not " + returnModeName(mode));
    }
    for (const LidarSurfaceExtension& x : spec_.extensions.surfaces) {  // every surface of its name
        bool found = false;
        for (size_t k = 0; k < scene_.surfaces.size(); ++k)
            if (scene_.surfaces[k].name == x.name) {
                reflectance_.resize(scene_.surfaces.size(), 1.0);
                reflectance_[k] = x.reflectance_factor;
                found = true;
            }
        if (!found)
            throw Error(spec_.source + ": [[extensions.surface]] name",
                        "\"" + x.name + "\" is not a surface of the scene " + scene_.source);
    }
    pattern_ = framePattern(spec_);
    local_.reserve(pattern_.size());
    for (const PatternBeam& b : pattern_) {
        const double ce = std::cos(b.elevation_rad);
        local_.emplace_back(ce * std::cos(b.azimuth_rad), ce * std::sin(b.azimuth_rad), std::sin(b.elevation_rad));
    }
}

struct LidarScanner::FrameSetup {
    double start_s = 0, end_s = 0;
    Pose start_pose, end_pose;
    SmokeField field;
    uint64_t key = 0;  ///< the start time's bits: keys the replay's noise draws
};

LidarScanner::FrameSetup LidarScanner::setup(double start_s) const
{
    FrameSetup f{start_s, start_s + (pattern_.empty() ? 0.0 : pattern_.back().time_s), {}, {}, {}};
    f.start_pose = scene_.sensorAt(mount_, f.start_s).pose;
    f.end_pose = scene_.sensorAt(mount_, f.end_s).pose;
    f.field = SmokeField::at(scene_.volumes, 0.5 * (f.start_s + f.end_s));
    f.field.prepare(spec_.wavelength_nm);
    std::memcpy(&f.key, &start_s, sizeof f.key);
    return f;
}

void LidarScanner::signal(const FrameSetup& f, size_t i, SurfaceHit* hit, BeamSignal& out) const
{
    const Pose pose = mount_.robot >= 0 ? scene_.sensorAt(mount_, f.start_s + pattern_[i].time_s).pose : f.start_pose;
    const Ray ray{pose.t, pose.rotate(local_[i]).normalized()};
    traceBeamSignalInto(out, ray, spec_.wavelength_nm, spec_.range_max_m, spec_.receiver, scene_, surfaces_, f.field,
                        hit, nullptr, reflectance_.empty() ? nullptr : &reflectance_);
}

double returnTolerance_m(const LidarSpec& spec)
{
    return 0.5 * 2.354820045 * pulseSigma_m(spec.receiver) + 4 * spec.range_sigma_m;
}

ReturnClass classifyReturn(double range_m, double surface_range_m, double tolerance_m)
{
    if (!(range_m > 0)) return ReturnClass::None;
    if (range_m < surface_range_m - tolerance_m) return ReturnClass::Short;
    if (range_m <= surface_range_m + tolerance_m) return ReturnClass::Surface;
    return ReturnClass::Beyond;
}

namespace {

/// The first kept return's class in `draws` noisy receptions of the beam: the shares of none,
/// short and at the surface.
void outcomeShares(const LidarSpec& spec, ReturnMode mode, const BeamSignal& sig, const Waveform& base, uint64_t key,
                   size_t beam, ExpectedBeam& x)
{
    const double tol = returnTolerance_m(spec);
    int count[4] = {0, 0, 0, 0};
    for (int k = 0; k < kOutcomeDraws; ++k) {
        KeyedRng rng(kOutcomeSeed, key, uint64_t(beam), uint64_t(k));
        // Each draw's noisy copy of the waveform and its echoes in storage kept for the thread.
        thread_local Waveform f;
        thread_local std::vector<LidarEcho> e;
        f = base;
        receiveEchoesIn(spec, sig, f, &rng, e);
        size_t kept[2];
        const int n_kept = selectReturnsInto(e, mode, spec.dual_second_strongest, kept);
        ++count[int(classifyReturn(n_kept == 0 ? 0.0 : e[kept[0]].range_m, x.surface_range_m, tol))];
    }
    x.p_none = float(count[int(ReturnClass::None)]) / kOutcomeDraws;
    x.p_short = float(count[int(ReturnClass::Short)]) / kOutcomeDraws;
    x.p_surface = float(count[int(ReturnClass::Surface)]) / kOutcomeDraws;
}

/// A preset's extensions on a replayed beam: its channel's range offset on the range and on where
/// the surface's echo reads (a range taken to 0 or less: none); a beam with a dropout d is not
/// clear, its chances of any return times 1 − d (none: d more).
void applyExtensions(const LidarExtensions& ext, const PatternBeam& b, ExpectedBeam& x)
{
    // The channel's offset moves what the replay reads and where the surface's echo reads alike.
    const double offset = ext.rangeOffset_m(b.channel);
    if (offset != 0) {
        if (std::isfinite(x.surface_range_m)) x.surface_range_m += float(offset);
        if (x.range_m > 0 && !(x.range_m + float(offset) > 0)) {  // no point, as frame() gives none
            x.range_m = 0;
            x.clear = false;
            x.p_none = 1, x.p_short = 0, x.p_surface = 0;
        } else if (x.range_m > 0) {
            x.range_m += float(offset);
        }
    }
    // A beam that may return nothing is no longer certain: judged by its chances, each kept with 1 − d.
    const double d = ext.dropout(b.channel, b.azimuth_rad);
    if (d > 0) {
        x.clear = false;
        x.p_none = float(d + (1 - d) * x.p_none);
        x.p_short = float((1 - d) * x.p_short);
        x.p_surface = float((1 - d) * x.p_surface);
    }
}

}  // namespace

ExpectedBeam LidarScanner::expectedBeam(const FrameSetup& f, const LidarSpec& low, size_t i, bool dimmer) const
{
    const PhysicalParams& p = spec_.receiver;
    SurfaceHit hit;
    thread_local BeamSignal sig;  // storage kept for the thread's next beam
    signal(f, i, &hit, sig);
    ExpectedBeam x;
    const Waveform base = pulsedWaveform(spec_.range_max_m, p, sig, 2);
    // What the receiver could see with the noise: its echoes at a threshold kClearMarginSd sd lower.
    const std::vector<LidarEcho> faint = receiveEchoes(low, sig, base, nullptr);
    const double pulse_m = 2.354820045 * pulseSigma_m(p);
    if (hit.hit && hit.t_m <= spec_.range_max_m) {
        x.surface = hit.surface;
        x.surface_range_m = float(hit.t_m);
        // Where its echo reads: the faint surface echo nearest the hit, within a pulse's length.
        double best = pulse_m;
        for (const LidarEcho& e : faint)
            if (e.source == EchoSource::Surface && std::abs(e.range_m - hit.t_m) < best)
                best = std::abs(e.range_m - hit.t_m), x.surface_range_m = float(e.range_m);
    }
    const std::vector<LidarEcho> echoes = receiveEchoes(spec_, sig, base, nullptr);
    const std::vector<size_t> kept = selectReturns(echoes, mode_, spec_.dual_second_strongest);
    double e_peak = 0;  // the kept echo's peak
    if (!kept.empty()) {
        const LidarEcho& e = echoes[kept.front()];
        x.range_m = float(e.range_m);
        x.peak_sd = float(e.peak / p.noise_floor);
        x.peak_noise = float(e.peak_noise);
        e_peak = e.peak;
        x.intensity = float(e.intensity);
        // Over the threshold in noise sd: for a peak out of another's run, of the rise and the
        // fall around its valley, each the difference of two noisy samples (√2 sd).
        x.margin_sd =
            float((e.standout - p.threshold_snr * p.noise_floor) / p.noise_floor / (e.pedestal > 0 ? M_SQRT2 : 1.0));
        x.source = uint8_t(e.source);
        // The echo must still be found at the lower threshold (a peak that no longer stands out
        // of the run it rises from there is lost to it) and no other source may speak.
        const bool alone = std::any_of(faint.begin(), faint.end(), [&](const LidarEcho& g) {
            return g.source == EchoSource::Surface && std::abs(g.range_m - e.range_m) < pulse_m;
        });
        // And one surface only: a footprint across an edge mixes two, whose echoes the scene's
        // reflectances weigh (a wall's base: the floor's beam loses its echo if the wall is darker).
        x.clear = e.source == EchoSource::Surface && !sig.mixed_surfaces && x.margin_sd >= kClearMarginSd && alone &&
            std::none_of(faint.begin(), faint.end(),
                         [](const LidarEcho& g) { return g.source != EchoSource::Surface; });
    }
    if (x.clear) {
        // Its peak at a half and a quarter of the surfaces' power: a half and a quarter of it for
        // an echo alone; the smoke's backscatter under it does not scale.
        for (const double share : {0.5, 0.25}) {
            if (!dimmer) break;
            BeamSignal dim = sig;
            for (Echo& e : dim.echoes)
                if (e.source == EchoSource::Surface) e.power *= share;
            dim.surface_power *= share;
            double best = pulse_m, ratio = 0;
            for (const LidarEcho& e : receiveEchoes(spec_, dim, pulsedWaveform(spec_.range_max_m, p, dim, 2), nullptr))
                if (std::abs(e.range_m - x.range_m) < best)
                    best = std::abs(e.range_m - x.range_m), ratio = e.peak / e_peak;
            (share == 0.5 ? x.peak_at_half : x.peak_at_quarter) = float(ratio);
        }
        const ReturnClass c = classifyReturn(x.range_m, x.surface_range_m, returnTolerance_m(spec_));
        x.p_none = 0;
        x.p_short = c == ReturnClass::Short;
        x.p_surface = c == ReturnClass::Surface;
    } else if (!waveformEchoes(base, low.receiver.threshold_snr * p.noise_floor, 1).empty()) {
        // Some run the noise could lift over the threshold (or merge with the blind zone's, and so
        // lose an echo): the chances from draws of the noise.
        outcomeShares(spec_, mode_, sig, base, f.key, i, x);
    }
    applyExtensions(spec_.extensions, pattern_[i], x);
    return x;
}

std::vector<ExpectedBeam> LidarScanner::expected(double start_s, bool dimmer) const
{
    const FrameSetup f = setup(start_s);
    LidarSpec low = spec_;
    low.receiver.threshold_snr = std::max(0.0, spec_.receiver.threshold_snr - kClearMarginSd);
    std::vector<ExpectedBeam> out(pattern_.size());
    tbb::parallel_for(size_t(0), pattern_.size(), [&](size_t i) { out[i] = expectedBeam(f, low, i, dimmer); });
    return out;
}

void LidarScanner::beamPoints(const FrameSetup& f, uint64_t index, size_t i, LidarFrame& fr,
                              std::vector<LidarPoint>& out) const
{
    const PatternBeam& b = pattern_[i];
    const Vec3& local = local_[i];
    thread_local BeamSignal sig;  // storage kept for the thread's next beam
    signal(f, i, nullptr, sig);
    KeyedRng rng(seed_, index, uint64_t(i));
    thread_local std::vector<LidarEcho> echoes;  // storage kept for the thread's next beam
    receiveEchoesInto(spec_, sig, &rng, echoes);
    // The extensions: a beam lost whole at its channel's and sector's dropout (its own draw, so
    // that the other beams' noise is the preset's), its channel's offset on each range.
    const double drop = spec_.extensions.dropout(b.channel, b.azimuth_rad);
    if (drop > 0 && KeyedRng(seed_ ^ kDropoutKey, index, uint64_t(i)).uniform() < drop) return;
    const double offset = spec_.extensions.rangeOffset_m(b.channel);
    size_t chosen[2], kept[2];
    const int n_chosen = selectReturnsInto(echoes, mode_, spec_.dual_second_strongest, chosen);
    size_t n_kept = 0;  // those still in front of the sensor after the channel's offset
    for (int k = 0; k < n_chosen; ++k)
        if (echoes[chosen[k]].range_m + offset > 0) kept[n_kept++] = chosen[k];
    for (size_t k = 0; k < n_kept; ++k) {
        const LidarEcho& e = echoes[kept[k]];
        LidarPoint q;
        const double range_m = e.range_m + offset;
        q.x = float(range_m * local.x());
        q.y = float(range_m * local.y());
        q.z = float(range_m * local.z());
        q.range_m = float(range_m);
        q.intensity = float(e.intensity);
        q.ring = uint16_t(b.channel);
        q.return_index = uint8_t(k);
        q.source = uint8_t(e.source);
        q.time_s = float(b.time_s);
        q.beam = uint32_t(i);
        out.push_back(q);
        if (k == 0 && !fr.range_image.empty()) {
            const size_t column = i / size_t(fr.channels), ch = size_t(b.channel);
            fr.range_image[ch * size_t(fr.columns) + column] = q.range_m;
        }
    }
}

LidarFrame LidarScanner::frame(double start_s, uint64_t index) const
{
    const FrameSetup f = setup(start_s);
    LidarFrame fr;
    fr.index = index;
    fr.start_s = f.start_s;
    fr.end_s = f.end_s;
    fr.start_pose = f.start_pose;
    fr.end_pose = f.end_pose;
    fr.channels = spec_.channels();
    fr.columns = frameColumns(spec_);
    const size_t n = pattern_.size();
    const bool spinning = spec_.pattern == PatternKind::Spinning;
    if (spinning) fr.range_image.assign(size_t(fr.channels) * size_t(fr.columns), 0.0f);
    // The beams in fixed chunks, each chunk's points (up to two a beam) in its own vector, joined
    // in chunk order: the frame is the same whatever the thread count, and no serial pass over
    // every beam's slots.
    constexpr size_t kChunk = 1024;
    std::vector<std::vector<LidarPoint>> parts((n + kChunk - 1) / kChunk);
    tbb::parallel_for(size_t(0), parts.size(), [&](size_t c) {
        std::vector<LidarPoint>& part = parts[c];
        part.reserve(2 * kChunk);
        for (size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i) beamPoints(f, index, i, fr, part);
    });
    size_t total = 0;
    for (const auto& part : parts) total += part.size();
    fr.points.reserve(total);
    for (const auto& part : parts) fr.points.insert(fr.points.end(), part.begin(), part.end());
    return fr;
}

}  // namespace smokescan
