#include "fit_bootstrap.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "smokescan/core/order_stats.hpp"

namespace smokescan::detail {

std::vector<double> beamThresholdSpread(const std::vector<std::vector<bool>>& failed,
                                        const std::vector<double>& S_at_scan)
{
    const size_t n_beams = failed.empty() ? 0 : failed.front().size();
    std::vector<double> mid(n_beams, NAN), separated;
    for (size_t i = 0; i < n_beams; ++i) {
        double err_max = -1, clean_min = 2;
        for (size_t k = 0; k < failed.size() && k < S_at_scan.size(); ++k) {
            const double S = S_at_scan[k];
            if (std::isnan(S)) continue;
            if (failed[k][i])
                err_max = std::max(err_max, S);
            else
                clean_min = std::min(clean_min, S);
        }
        if (err_max >= 0 && clean_min <= 1 && err_max < clean_min)
            separated.push_back(mid[i] = 0.5 * (err_max + clean_min));
    }
    const double median = separated.empty() ? 0.0 : quantile(separated, 0.5);
    for (double& m : mid) m = std::isnan(m) ? 0.0 : m - median;
    return mid;
}

void drawErrorCounts(const GroupModel& m, const std::vector<double>& S_true, KeyedRng& rng, GroupCounts& c)
{
    for (size_t k = 0; k < c.t.size() && k < S_true.size(); ++k) {
        const double S = S_true[k];
        if (std::isnan(S)) continue;
        int e = 0;
        if (m.width > 0) {
            const double p = errorProbability(S, m.S_star, m.width, m.logistic);
            for (int i = 0; i < c.n[k]; ++i) e += rng.uniform() < p;
        } else {
            for (int i = 0; i < c.n[k]; ++i)
                e += S < m.S_star + (size_t(i) < m.beam_offset.size() ? m.beam_offset[size_t(i)] : 0.0);
        }
        c.e[k] = e;
    }
}

uint64_t dataKey(const std::vector<double>& saturation, const std::vector<const std::vector<int>*>& counts)
{
    uint64_t h = 1469598103934665603ull;
    auto mix = [&h](uint64_t v) {
        for (int i = 0; i < 8; ++i) {
            h ^= (v >> (8 * i)) & 0xffu;
            h *= 1099511628211ull;
        }
    };
    for (double x : saturation) {
        uint64_t bits;
        std::memcpy(&bits, &x, sizeof bits);
        mix(bits);
    }
    for (const auto* c : counts)
        for (int e : *c) mix(uint64_t(uint32_t(e)));
    return h;
}

double finiteSpread(const std::vector<double>& v, int min_n)
{
    double mean = 0, q = 0;
    int n = 0;
    for (double x : v)
        if (std::isfinite(x)) {
            mean += x;
            ++n;
        }
    if (n < std::max(2, min_n)) return NAN;
    mean /= n;
    for (double x : v)
        if (std::isfinite(x)) q += (x - mean) * (x - mean);
    return std::sqrt(q / (n - 1));
}

}  // namespace smokescan::detail
