#include "smokescan/core/order_stats.hpp"

#include <algorithm>
#include <cmath>

namespace smokescan {

double quantile(std::vector<double> v, double q)
{
    if (v.empty()) return NAN;
    // Position h = q·(n − 1) between order statistics ⌊h⌋ and ⌊h⌋ + 1; partial selection, O(n).
    const double h = std::clamp(q, 0.0, 1.0) * double(v.size() - 1);
    const size_t lo = size_t(std::floor(h));
    std::nth_element(v.begin(), v.begin() + long(lo), v.end());
    const double a = v[lo];
    if (lo + 1 >= v.size() || h == double(lo)) return a;
    const double b = *std::min_element(v.begin() + long(lo) + 1, v.end());
    return a + (h - double(lo)) * (b - a);
}

double median(std::vector<double> v) { return quantile(std::move(v), 0.5); }

}  // namespace smokescan
