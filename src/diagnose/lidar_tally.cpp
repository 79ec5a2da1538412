// A 3D lidar's recorded frames against their replays, beam by beam (diagnose/lidar_diagnosis.hpp).
#include <algorithm>
#include <cmath>
#include <limits>

#include "smokescan/core/error.hpp"
#include "smokescan/diagnose/lidar_diagnosis.hpp"

namespace smokescan {

LidarTally::LidarTally(const std::vector<PatternBeam>& pattern, int channels, double tolerance_m, double max_range_m)
    : pattern_(pattern), channels_(channels), tolerance_m_(tolerance_m), max_range_m_(max_range_m)
{
    if (!(tolerance_m_ > 0)) throw Error("lidar diagnosis", "the return tolerance must be > 0");
    if (channels_ <= 0 || pattern_.empty()) throw Error("lidar diagnosis", "the sensor's pattern has no beams");
    by_ring_.resize(size_t(channels_));
    for (size_t i = 0; i < pattern_.size(); ++i) {
        const int c = pattern_[i].channel;
        if (c < 0 || c >= channels_)
            throw Error("lidar diagnosis", "a beam's channel is outside the sensor's channels");
        by_ring_[size_t(c)].emplace_back(pattern_[i].time_s, uint32_t(i));
    }
    for (auto& ring : by_ring_) std::sort(ring.begin(), ring.end());
    for (Fold& f : fold_) {
        f.clear.assign(pattern_.size(), 0);
        f.missed.assign(pattern_.size(), 0);
        f.residual_m.resize(size_t(channels_));
        f.residual_surface.resize(size_t(channels_));
    }
}

namespace {

/// The beam of `ring` fired nearest `time_s`, when it is nearer than half the gap to the ring's
/// neighbouring beams; -1 otherwise.
long nearestBeam(const std::vector<std::pair<double, uint32_t>>& ring, double time_s)
{
    if (ring.empty()) return -1;
    auto it = std::lower_bound(ring.begin(), ring.end(), std::make_pair(time_s, uint32_t(0)));
    size_t k = size_t(it - ring.begin());
    if (k == ring.size() || (k > 0 && time_s - ring[k - 1].first < ring[k].first - time_s)) --k;
    const double before = k > 0 ? ring[k].first - ring[k - 1].first : std::numeric_limits<double>::infinity();
    const double after =
        k + 1 < ring.size() ? ring[k + 1].first - ring[k].first : std::numeric_limits<double>::infinity();
    double half_gap = 0.5 * std::min(before, after);
    if (!std::isfinite(half_gap)) half_gap = 1e-3;  // a ring of one beam: within a millisecond
    return std::abs(time_s - ring[k].first) <= half_gap ? long(ring[k].second) : -1;
}

/// Whether the point lies within kMatchDeg of its beam's direction in the sensor frame.
bool alongBeam(const PatternBeam& b, const LidarPoint& p)
{
    const double r = std::sqrt(double(p.x) * p.x + double(p.y) * p.y + double(p.z) * p.z);
    if (!(r > 0)) return false;
    const double ce = std::cos(b.elevation_rad);
    const double dot =
        (ce * std::cos(b.azimuth_rad) * p.x + ce * std::sin(b.azimuth_rad) * p.y + std::sin(b.elevation_rad) * p.z) / r;
    return dot >= std::cos(kMatchDeg * M_PI / 180);
}

}  // namespace

void LidarTally::add(const std::vector<ExpectedBeam>& expected, const std::vector<LidarPoint>& recorded, int fold)
{
    const size_t n = pattern_.size();
    if (expected.size() != n) throw Error("lidar diagnosis", "the replay's beams are not the pattern's");
    if (fold != 0 && fold != 1) throw Error("lidar diagnosis", "a fold is 0 or 1");
    std::vector<float> got(n, std::numeric_limits<float>::quiet_NaN());
    // The intensity of a clear beam's point at its surface (any return: in dual mode the first
    // may be a faint echo the noise lifted before it), the nearest to the replay's range.
    std::vector<float> got_intensity(n, 0), got_range(n, 0), off_m(n, std::numeric_limits<float>::infinity());
    for (const LidarPoint& p : recorded) {
        const long b = p.ring < channels_ ? nearestBeam(by_ring_[p.ring], double(p.time_s)) : -1;
        const bool in_range = std::isfinite(p.range_m) && p.range_m <= 1.01 * max_range_m_;
        const bool along = b >= 0 && in_range && alongBeam(pattern_[size_t(b)], p);
        if (along && expected[size_t(b)].clear) {
            const float off = std::abs(p.range_m - expected[size_t(b)].range_m);
            if (off <= tolerance_m_ && off < off_m[size_t(b)])
                off_m[size_t(b)] = off, got_intensity[size_t(b)] = p.intensity, got_range[size_t(b)] = p.range_m;
        }
        if (p.return_index != 0) continue;
        if (!along || !std::isnan(got[size_t(b)])) {
            ++unmatched_;
            continue;
        }
        got[size_t(b)] = p.range_m;
    }
    Fold& f = fold_[fold];
    for (size_t i = 0; i < n; ++i) {
        if (!expected[i].clear) {
            addOutcomes(expected[i], std::isnan(got[i]) ? 0.0 : double(got[i]), f);
            continue;
        }
        ++f.clear[i];
        const int surface = expected[i].surface;
        if (surface >= 0) {
            std::vector<uint32_t>& on = f.clear_on[surface];
            if (on.empty()) on.assign(n, 0), f.missed_on[surface].assign(n, 0);
            ++on[i];
        }
        if (std::isnan(got[i])) {
            ++f.missed[i];
            if (surface >= 0) ++f.missed_on[surface][i];
        } else {
            const size_t c = size_t(pattern_[i].channel);
            f.residual_m[c].push_back(got[i] - expected[i].range_m);
            f.residual_surface[c].push_back(surface);
            const ExpectedBeam& x = expected[i];
            const float recorded = got_intensity[i];
            if (keep_intensities_ && surface >= 0 && x.intensity > 0 && std::isfinite(off_m[i])) {
                if (std::isfinite(recorded) && recorded > 0)
                    intensities_.push_back({surface, recorded, got_range[i], x.intensity, x.range_m, x.peak_sd,
                                            x.peak_noise, x.peak_at_half, x.peak_at_quarter});
                else
                    ++unusable_intensities_;  // NaN, infinite, zero or negative: no reflectivity to fit
            }
        }
    }
    ++frames_;
}

namespace {

/// One beam's outcome into the sums: p, its chance, is a share of `draws` noise draws (unbiased);
/// its variance is taken at (p·draws + ½)/(draws + 1), off 0 and 1 (a chance under 1/draws is seen
/// as 0 by the draws but not by the recorder), with the draws' own error beside the beam's.
void count(LidarOutcomes& o, bool happened, double p, double draws)
{
    const double q = (p * draws + 0.5) / (draws + 1);
    o.observed += happened;
    o.expected += p;
    o.variance += q * (1 - q) * (1 + 1 / draws);
    ++o.beams;
}

}  // namespace

void LidarTally::addOutcomes(const ExpectedBeam& x, double recorded_m, Fold& f) const
{
    if (x.p_none >= 1) return;  // nothing the noise could lift over the threshold
    const ReturnClass c = classifyReturn(recorded_m, x.surface_range_m, tolerance_m_);
    count(f.short_returns, c == ReturnClass::Short, x.p_short, kOutcomeDraws);
    // The surface's returns given the first return is not short (a smoke echo before it, which
    // the short returns' own test speaks for).
    if (x.surface < 0 || c == ReturnClass::Short || x.p_short >= 1) return;
    count(f.surface_returns[x.surface], c == ReturnClass::Surface, x.p_surface / (1 - x.p_short),
          kOutcomeDraws * (1 - x.p_short));
}

}  // namespace smokescan
