#include "smokescan/camera/saturation.hpp"
#include "smokescan/core/order_stats.hpp"

#include <algorithm>
#include <cmath>

namespace smokescan {

double hsvSaturation(double r, double g, double b)
{
    const double mx = std::max({r, g, b}), mn = std::min({r, g, b});
    return mx > 0 ? (mx - mn) / mx : 0.0;
}

SaturationStats saturationStats(std::vector<double> v)
{
    SaturationStats s;
    s.pixels = (long long)v.size();
    if (v.empty()) return s;
    double sum = 0, sum2 = 0;
    for (double x : v) {
        sum += x;
        sum2 += x * x;
    }
    s.mean = sum / v.size();
    s.stddev = std::sqrt(std::max(0.0, sum2 / v.size() - s.mean * s.mean));
    s.median = median(std::move(v));
    return s;
}

}  // namespace smokescan
