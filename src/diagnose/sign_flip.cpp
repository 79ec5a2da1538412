#include "sign_flip.hpp"

#include <cmath>

#include "smokescan/core/random.hpp"

namespace smokescan::detail {

double signFlipP(const std::vector<double>& gains, long long flips, uint64_t seed)
{
    std::vector<double> g;
    for (double x : gains)
        if (x != 0) g.push_back(x);
    if (g.empty()) return 1.0;
    double total = 0;
    for (double x : g) total += x;
    const double tol = 1e-12 * (1 + std::abs(total));
    long long hits = 0, n = 0;
    if (g.size() <= 20) {
        const long long N = 1LL << g.size();
        for (long long mask = 0; mask < N; ++mask) {
            double s = 0;
            for (size_t i = 0; i < g.size(); ++i) s += (mask >> i & 1) ? -g[i] : g[i];
            hits += s >= total - tol;
        }
        n = N;
    } else {
        KeyedRng rng(seed, 0x5f1, 0);
        for (long long it = 0; it < flips; ++it) {
            double s = 0;
            for (double x : g) s += rng.uniform() < 0.5 ? -x : x;
            hits += s >= total - tol;
        }
        hits += 1;  // the observed signs themselves
        n = flips + 1;
    }
    return double(hits) / double(n);
}

}  // namespace smokescan::detail
