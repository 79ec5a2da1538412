#include "smokescan/calib/saturation.hpp"

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
    const size_t mid = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + mid, v.end());
    s.median = v[mid];
    if (v.size() % 2 == 0) s.median = 0.5 * (s.median + *std::max_element(v.begin(), v.begin() + mid));
    return s;
}

}  // namespace smokescan
