// Each cause of a 3D lidar's diagnosis searched on the even frames and tested on the odd ones
// (diagnose/lidar_diagnosis.hpp, docs/diagnosis.md "A 3D lidar's frames").
#include <algorithm>
#include <cmath>
#include <numeric>

#include "ceres_fit.hpp"
#include "range_offset_residual.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/order_stats.hpp"
#include "smokescan/diagnose/lidar_diagnosis.hpp"

namespace smokescan {
namespace {

/// Missed returns inside a group of beams and outside it.
struct Split {
    double m_in = 0, n_in = 0, m_out = 0, n_out = 0;
    double rateIn() const { return n_in > 0 ? m_in / n_in : 0; }
    double rateOut() const { return n_out > 0 ? m_out / n_out : 0; }
};

double binomialLl(double m, double n, double p)
{
    double ll = 0;
    if (m > 0) ll += m * std::log(p);
    if (n - m > 0) ll += (n - m) * std::log1p(-p);
    return ll;
}

/// The likelihood ratio statistic 2·Δln L of "inside and outside miss at their own rates" over
/// "one rate for all", signed by whether inside misses more: under no difference, a standard
/// normal's square with that sign.
double signedRoot(const Split& s)
{
    if (s.n_in <= 0 || s.n_out <= 0) return 0;
    const double pa = (s.m_in + s.m_out) / (s.n_in + s.n_out);
    const double lr = 2 *
        (binomialLl(s.m_in, s.n_in, s.rateIn()) + binomialLl(s.m_out, s.n_out, s.rateOut()) -
         binomialLl(s.m_in + s.m_out, s.n_in + s.n_out, pa));
    const double r = std::sqrt(std::max(0.0, lr));
    return s.rateIn() > s.rateOut() ? r : -r;
}

/// The held-out test of a dropout split: its excess, the one-sided p and the gain in nats.
void testDropout(const Split& s, LidarFinding& f)
{
    const double z = signedRoot(s);
    const double pi = s.rateIn(), po = s.rateOut();
    f.tested = s.n_in > 0 && s.n_out > 0;
    f.effect = pi - po;
    f.base_rate = po;
    f.effect_se = std::sqrt(pi * (1 - pi) / std::max(1.0, s.n_in) + po * (1 - po) / std::max(1.0, s.n_out));
    f.gain_nats = 0.5 * z * std::abs(z);
    f.p_value = f.tested ? 0.5 * std::erfc(z / std::sqrt(2.0)) : 1;
}

/// What a test leaves out: the clear beams of other causes' candidates (the surface's from the
/// sector's test, the sector's from the channel's), chosen on the search fold alone so that the
/// held-out fold only tests.
struct Excluded {
    std::vector<char> beam;  ///< per beam of the pattern: left out whole (a sector's or a ring's)
    std::vector<int> surfaces;  ///< the clear beams on these surfaces left out
};

/// Beam i's clear beams and misses in fold f less those `ex` leaves out: {clear, missed}.
std::pair<double, double> clearOf(const LidarTally::Fold& f, size_t i, const Excluded& ex)
{
    if (ex.beam[i]) return {0, 0};
    double n = f.clear[i], m = f.missed[i];
    for (int s : ex.surfaces) {
        const auto on = f.clear_on.find(s);
        if (on == f.clear_on.end()) continue;
        n -= on->second[i];
        m -= f.missed_on.at(s)[i];
    }
    return {n, m};
}

int sectorBin(double azimuth_rad, int bins)
{
    const double deg = azimuth_rad * 180 / M_PI;
    const double u = std::fmod(deg + 180, 360.0);
    return std::min(bins - 1, int(std::floor((u < 0 ? u + 360 : u) / (360.0 / bins))));
}

/// Counts of a fold by sector bin, less what `ex` leaves out.
std::vector<Split> binCounts(const LidarTally& t, int fold, int bins, const Excluded& ex)
{
    std::vector<Split> out(static_cast<size_t>(bins));
    const LidarTally::Fold& f = t.fold(fold);
    for (size_t i = 0; i < t.pattern().size(); ++i) {
        Split& s = out[size_t(sectorBin(t.pattern()[i].azimuth_rad, bins))];
        const auto [n, m] = clearOf(f, i, ex);
        s.n_in += n;
        s.m_in += m;
    }
    return out;
}

/// Whether bin b lies in the run of `width` bins from `start` (wrapping at 180°).
bool inRun(int b, int start, int width, int bins) { return ((b - start) % bins + bins) % bins < width; }

Split runSplit(const std::vector<Split>& bin, int start, int width)
{
    Split s;
    const int bins = int(bin.size());
    for (int b = 0; b < bins; ++b) {
        const bool in = inRun(b, start, width, bins);
        (in ? s.n_in : s.n_out) += bin[size_t(b)].n_in;
        (in ? s.m_in : s.m_out) += bin[size_t(b)].m_in;
    }
    return s;
}

/// The window's sector: the run of bins whose missed returns most exceed the rest's on fold 0
/// (a scan statistic), tested on fold 1.
LidarFinding windowSector(const LidarTally& t, const LidarDiagnosisConfig& cfg, const Excluded& ex, int& start,
                          int& width)
{
    LidarFinding f;
    f.cause = LidarCause::WindowSector;
    f.floor = cfg.min_dropout;
    const int bins = int(std::lround(360 / cfg.sector_deg));
    const int widest = std::max(1, std::min(bins - 1, int(std::lround(cfg.max_sector_deg / cfg.sector_deg))));
    const std::vector<Split> search = binCounts(t, 0, bins, ex);
    double best = 0;
    start = -1;
    width = 0;
    for (int s = 0; s < bins; ++s)
        for (int w = 1; w <= widest; ++w) {
            const double z = signedRoot(runSplit(search, s, w));
            if (z > best) best = z, start = s, width = w;
        }
    if (start < 0) return f;
    f.from_deg = -180 + start * cfg.sector_deg;
    f.to_deg = f.from_deg + width * cfg.sector_deg;
    if (f.to_deg > 180) f.to_deg -= 360;  // a sector across 180°: from > to
    testDropout(runSplit(binCounts(t, 1, bins, ex), start, width), f);
    return f;
}

/// The clear beams of a fold in a group (the beams `in` selects) against the rest, less what `ex`
/// leaves out.
template <typename In>
Split groupSplit(const LidarTally& t, int fold, const Excluded& ex, In in)
{
    Split s;
    const LidarTally::Fold& f = t.fold(fold);
    for (size_t i = 0; i < t.pattern().size(); ++i) {
        const auto [n, m] = clearOf(f, i, ex);
        (in(i) ? s.n_in : s.n_out) += n;
        (in(i) ? s.m_in : s.m_out) += m;
    }
    return s;
}

/// A channel dropping returns: the ring whose missed returns most exceed the others' on fold 0,
/// tested on fold 1.
LidarFinding droppingChannel(const LidarTally& t, const LidarDiagnosisConfig& cfg, const Excluded& ex)
{
    LidarFinding f;
    f.cause = LidarCause::DroppingChannel;
    f.floor = cfg.min_dropout;
    auto ringSplit = [&](int fold, int ring) {
        return groupSplit(t, fold, ex, [&](size_t i) { return t.pattern()[i].channel == ring; });
    };
    double best = 0;
    for (int c = 0; c < t.channels(); ++c) {
        const double z = signedRoot(ringSplit(0, c));
        if (z > best) best = z, f.ring = c;
    }
    if (f.ring < 0) return f;
    testDropout(ringSplit(1, f.ring), f);
    return f;
}

/// The library's median (core/order_stats) of float residuals.
double median(const std::vector<float>& v) { return smokescan::median(std::vector<double>(v.begin(), v.end())); }

/// Every `stride`-th of v, at most `cap` of them.
std::vector<float> strided(const std::vector<float>& v, size_t cap)
{
    if (v.size() <= cap) return v;
    std::vector<float> out;
    const double step = double(v.size()) / double(cap);
    for (size_t k = 0; k < cap; ++k) out.push_back(v[size_t(double(k) * step)]);
    return out;
}

/// Fold f's residuals by channel, without those on surface `skip` (the surface's candidate: its
/// ranges are as suspect as its returns; −1: none).
std::vector<std::vector<float>> residualsBut(const LidarTally::Fold& f, int skip)
{
    std::vector<std::vector<float>> out(f.residual_m.size());
    for (size_t c = 0; c < out.size(); ++c)
        for (size_t k = 0; k < f.residual_m[c].size(); ++k)
            if (f.residual_surface[c][k] != skip || skip < 0) out[c].push_back(f.residual_m[c][k]);
    return out;
}

/// A channel's range bias: the ring whose median residual stands furthest from the others' on
/// fold 0, fitted on fold 1 beside an offset common to all (Huber loss, Ceres' covariance); the
/// residuals on surface `skip` left out of both (−1: none).
LidarFinding biasedChannel(const LidarTally& t, double range_sigma_m, const LidarDiagnosisConfig& cfg, int skip)
{
    LidarFinding f;
    f.cause = LidarCause::BiasedChannel;
    f.floor = cfg.min_bias_sd * range_sigma_m;
    const std::vector<std::vector<float>> a = residualsBut(t.fold(0), skip), b = residualsBut(t.fold(1), skip);
    const double sd0 = robustResidualSd({&a});
    std::vector<float> all;
    for (const auto& r : a) all.insert(all.end(), r.begin(), r.end());
    const double med0 = median(std::move(all));
    double best = 0;
    for (int c = 0; c < t.channels(); ++c) {
        const auto& r = a[size_t(c)];
        if (r.size() < 10 || !(sd0 > 0)) continue;
        const double z = std::abs(median(r) - med0) / (1.2533 * sd0 / std::sqrt(double(r.size())));
        if (z > best) best = z, f.ring = c;
    }
    if (f.ring < 0 || b[size_t(f.ring)].size() < 10) return f;
    const double sd = std::max(robustResidualSd({&b}), 1e-6);
    // At most 2e5 residuals on each side: the rest's offset is then known far better than the channel's.
    constexpr size_t kCap = 200'000;
    std::vector<float> rest;
    for (int c = 0; c < t.channels(); ++c)
        if (c != f.ring) rest.insert(rest.end(), b[size_t(c)].begin(), b[size_t(c)].end());
    if (rest.size() < 10) return f;
    double x[2] = {median(rest), median(b[size_t(f.ring)]) - median(rest)};
    ceres::Problem problem;
    auto addAll = [&](const std::vector<float>& v, bool on) {
        for (float r : strided(v, kCap))
            problem.AddResidualBlock(new ceres::AutoDiffCostFunction<detail::RangeOffsetResidual, 1, 2>(
                                         new detail::RangeOffsetResidual(double(r), sd, on)),
                                     new ceres::HuberLoss(3.0), x);
    };
    addAll(b[size_t(f.ring)], true);
    addAll(rest, false);
    ceres::Solver::Summary summary;
    if (!detail::solveQuiet(problem, detail::denseOptions(100, 1e-10), summary)) return f;
    // The sandwich (each residual its own cluster): the Huber fit's model-based covariance holds
    // for Gaussian residuals only, and a lidar's have tails (mixed pixels at edges, multipath).
    std::vector<long long> each(size_t(problem.NumResidualBlocks()));
    std::iota(each.begin(), each.end(), 0LL);
    const detail::ClusterCovariance cov =
        detail::clusterRobustCovariance(problem, {x}, each, detail::ClusterCount::WithData);
    if (!(cov.robust(1, 1) > 0)) return f;
    f.tested = true;
    f.effect = x[1];
    f.effect_se = std::sqrt(cov.robust(1, 1));
    const double z = f.effect / f.effect_se;
    f.gain_nats = 0.5 * z * z;
    f.p_value = std::erfc(std::abs(z) / std::sqrt(2.0));
    return f;
}

/// An outcome's recorded count against its chance: the excess share, its se, z.
void testOutcomes(const LidarOutcomes& o, LidarFinding& f)
{
    f.tested = o.beams > 0 && o.variance > 0;
    if (!f.tested) return;
    const double z = (o.observed - o.expected) / std::sqrt(o.variance);
    f.effect = (o.observed - o.expected) / double(o.beams);
    f.effect_se = std::sqrt(o.variance) / double(o.beams);
    f.gain_nats = 0.5 * z * z;
    f.p_value = 0.5 * std::erfc(z / std::sqrt(2.0));  // one-sided, more than its chance
}

/// Smoke echoes taken as first returns: more short returns than the replay's chances, over every
/// frame (nothing is chosen, so nothing needs holding out).
LidarFinding smokeFirstReturns(const LidarTally& t, const LidarDiagnosisConfig& cfg)
{
    LidarFinding f;
    f.cause = LidarCause::SmokeFirstReturns;
    f.floor = cfg.min_dropout;
    LidarOutcomes o = t.fold(0).short_returns;
    o += t.fold(1).short_returns;
    testOutcomes(o, f);
    return f;
}

/// The clear beams on `surface` against the other clear beams of a fold.
Split surfaceMissSplit(const LidarTally& t, int fold, int surface)
{
    const LidarTally::Fold& f = t.fold(fold);
    Split s;
    for (size_t i = 0; i < t.pattern().size(); ++i) s.n_out += f.clear[i], s.m_out += f.missed[i];
    const auto on = f.clear_on.find(surface);
    if (on == f.clear_on.end()) return s;
    const std::vector<uint32_t>& missed = f.missed_on.at(surface);
    for (size_t i = 0; i < t.pattern().size(); ++i) {
        s.n_in += on->second[i], s.m_in += missed[i];
        s.n_out -= on->second[i], s.m_out -= missed[i];
    }
    return s;
}

/// A surface's threshold or reflectance off: the surface whose returns stand furthest from what
/// the replay expects on fold 0 — its uncertain beams' returns against their chance (in their own
/// error, 20 beams at least), or its clear beams (20 at least) missing beyond the other clear beams' — tested
/// on fold 1, two-sided, both parts in one z (Stouffer's: they count different beams); the
/// effect is the uncertain beams' share of returns over their chance (< 0: fewer), else the
/// clear beams' share of returns below the others'.
LidarFinding surfaceThreshold(const LidarTally& t, const LidarDiagnosisConfig& cfg)
{
    LidarFinding f;
    f.cause = LidarCause::SurfaceThreshold;
    f.floor = cfg.min_dropout;
    auto outcomes = [&](int fold, int surface) -> const LidarOutcomes* {
        const auto it = t.fold(fold).surface_returns.find(surface);
        const bool usable =
            it != t.fold(fold).surface_returns.end() && it->second.beams >= 20 && it->second.variance > 0;
        return usable ? &it->second : nullptr;
    };
    std::vector<int> surfaces;
    for (const auto& [s, o] : t.fold(0).surface_returns) surfaces.push_back(s);
    for (const auto& [s, on] : t.fold(0).clear_on) surfaces.push_back(s);
    // Like the uncertain beams, the clear ones count from 20 beams on (a surface seen by a few
    // beams would otherwise be named on a miss or two).
    auto misses = [&](int fold, int surface) {
        Split s = surfaceMissSplit(t, fold, surface);
        return s.n_in >= 20 ? s : Split{};
    };
    double best = 0;
    for (int s : surfaces) {
        const LidarOutcomes* o = outcomes(0, s);
        const double z_out = o ? std::abs(o->observed - o->expected) / std::sqrt(o->variance) : 0.0;
        const double z = std::max(z_out, signedRoot(misses(0, s)));
        if (z > best) best = z, f.surface = s;
    }
    if (f.surface < 0) return f;
    const LidarOutcomes* o = outcomes(1, f.surface);
    const Split miss = misses(1, f.surface);
    const bool by_misses = miss.n_in > 0 && miss.n_out > 0;
    double z = 0;
    if (o) {
        testOutcomes(*o, f);
        z = f.effect / f.effect_se;
    }
    if (by_misses) {
        const double z_miss = -signedRoot(miss);  // fewer returns: < 0, as the outcomes' z
        if (!o) {
            testDropout(miss, f);
            f.effect = -f.effect;
        }
        z = o ? (z + z_miss) / std::sqrt(2.0) : z_miss;
        f.tested = true;
    }
    if (!f.tested) return f;
    f.gain_nats = 0.5 * z * z;
    f.p_value = std::erfc(std::abs(z) / std::sqrt(2.0));
    return f;
}

/// Both folds' stats of the beams `in` selects.
template <typename In>
LidarGroupStats groupStats(const LidarTally& t, In in)
{
    LidarGroupStats g;
    for (int k = 0; k < 2; ++k)
        for (size_t i = 0; i < t.pattern().size(); ++i)
            if (in(i)) {
                g.clear += t.fold(k).clear[i];
                g.missed += t.fold(k).missed[i];
            }
    g.matched = g.clear - g.missed;
    return g;
}

}  // namespace

const char* lidarCauseName(LidarCause c)
{
    switch (c) {
    case LidarCause::DroppingChannel:
        return "dropping_channel";
    case LidarCause::WindowSector:
        return "window_sector";
    case LidarCause::BiasedChannel:
        return "biased_channel";
    case LidarCause::SmokeFirstReturns:
        return "smoke_first_returns";
    case LidarCause::SurfaceThreshold:
        return "surface_threshold";
    }
    return "?";
}

LidarDiagnosis diagnoseLidar(const LidarTally& t, double range_sigma_m, const LidarDiagnosisConfig& cfg)
{
    if (!(cfg.level > 0 && cfg.level < 1)) throw Error("lidar diagnosis", "the level must lie in (0, 1)");
    if (!(cfg.sector_deg >= 0.5 && cfg.sector_deg <= 90) ||
        std::abs(360 / cfg.sector_deg - std::round(360 / cfg.sector_deg)) > 1e-9)
        throw Error("lidar diagnosis", "the sector bins must be 0.5 to 90 degrees wide and divide 360");
    if (!(cfg.max_sector_deg >= cfg.sector_deg && cfg.max_sector_deg <= 180))
        throw Error("lidar diagnosis", "the widest sector must be one bin to 180 degrees");
    LidarDiagnosis d;
    d.frames = t.frames();
    d.beams = (long long)(t.frames() * t.pattern().size());
    d.unmatched_points = t.unmatched();
    d.sector_deg = cfg.sector_deg;
    for (int k = 0; k < 2; ++k) {
        long long clear = 0;
        for (uint32_t c : t.fold(k).clear) clear += c;
        if (clear == 0)
            throw Error("lidar diagnosis",
                        std::string("the ") + (k == 0 ? "even" : "odd") +
                            " frames have no beam the replay is sure of (clear air, a surface in "
                            "range): nothing to compare");
        d.clear += clear;
    }
    d.range_sd_m = robustResidualSd({&t.fold(0).residual_m, &t.fold(1).residual_m});
    const int bins = int(std::lround(360 / cfg.sector_deg));
    for (int c = 0; c < t.channels(); ++c) {
        LidarGroupStats g = groupStats(t, [&](size_t i) { return t.pattern()[i].channel == c; });
        std::vector<float> r = t.fold(0).residual_m[size_t(c)];
        r.insert(r.end(), t.fold(1).residual_m[size_t(c)].begin(), t.fold(1).residual_m[size_t(c)].end());
        g.median_residual_m = median(std::move(r));
        d.rings.push_back(g);
    }
    for (int b = 0; b < bins; ++b) {
        LidarGroupStats g = groupStats(t, [&](size_t i) { return sectorBin(t.pattern()[i].azimuth_rad, bins) == b; });
        g.median_residual_m = NAN;  // residuals are kept by channel
        d.sectors.push_back(g);
    }
    const double each = cfg.level / 5;  // Bonferroni over the five causes
    auto judge = [&](LidarFinding& f) { f.named = f.tested && f.p_value < each && std::abs(f.effect) >= f.floor; };
    // A surface darker than the scene says loses its certain echoes too (the replay was sure of
    // them at the scene's reflectance), and reads them at other ranges: in a sector or a ring they
    // would pass for a dirty window or a channel's bias. The surface candidate (chosen on the even
    // frames) is the suspect: its clear beams are left out of the sector's and the bias's search
    // and test, named or not (whether it is named is the odd frames' word, which the even frames'
    // search must not hear).
    LidarFinding surface = surfaceThreshold(t, cfg);
    judge(surface);
    Excluded ex{std::vector<char>(t.pattern().size(), 0), {}};
    if (surface.surface >= 0) ex.surfaces.push_back(surface.surface);
    int start = -1, width = 0;
    LidarFinding window = windowSector(t, cfg, ex, start, width);
    judge(window);
    // The channel's search and test leave out the window's candidate sector, named or not, but
    // keep the surface's clear beams: a ring sees many surfaces and a wall many rings, so that a
    // ring's misses among all its beams stay the ring's (a dark wall's, spread over the rings that
    // see it, stay under a channel's floor), where a wall seen within a few degrees is a sector.
    ex.surfaces.clear();
    for (size_t i = 0; i < t.pattern().size(); ++i)
        if (width > 0 && inRun(sectorBin(t.pattern()[i].azimuth_rad, bins), start, width, bins)) ex.beam[i] = 1;
    LidarFinding channel = droppingChannel(t, cfg, ex);
    judge(channel);
    LidarFinding bias = biasedChannel(t, range_sigma_m, cfg, surface.surface);
    judge(bias);
    LidarFinding smoke = smokeFirstReturns(t, cfg);
    judge(smoke);
    d.tried = {channel, window, bias, smoke, surface};
    for (int k = 0; k < 2; ++k)
        for (const auto& [s, o] : t.fold(k).surface_returns) d.surfaces[s] += o;
    for (const LidarFinding& f : d.tried)
        if (f.named) d.verdict += (d.verdict.empty() ? "" : ", ") + std::string(lidarCauseName(f.cause));
    if (d.verdict.empty()) d.verdict = "none";
    return d;
}

double robustResidualSd(std::initializer_list<const std::vector<std::vector<float>>*> sets)
{
    std::vector<double> all;
    for (const auto* by_channel : sets)
        for (const auto& r : *by_channel) all.insert(all.end(), r.begin(), r.end());
    if (all.empty()) return NAN;
    const double m = smokescan::median(all);
    for (double& x : all) x = double(float(std::abs(x - m)));  // as the residuals are kept: floats
    return 1.4826 * smokescan::median(std::move(all));
}

}  // namespace smokescan
