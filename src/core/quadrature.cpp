#include "smokescan/core/quadrature.hpp"

#include <array>
#include <cmath>

namespace smokescan {
namespace {

/// Φ⁻¹(p) by bisection on Φ(z) = erfc(−z/√2)/2 (to 1e-15: done once).
double normalQuantile(double p)
{
    double lo = -40, hi = 40;
    for (int it = 0; it < 200; ++it) {
        const double mid = 0.5 * (lo + hi);
        (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

}  // namespace

const double* normalNodes()
{
    static const std::array<double, kNormalNodes> nodes = [] {
        std::array<double, kNormalNodes> z{};
        double var = 0;
        for (int i = 0; i < kNormalNodes; ++i) {
            z[size_t(i)] = normalQuantile((i + 0.5) / kNormalNodes);
            var += z[size_t(i)] * z[size_t(i)] / kNormalNodes;
        }
        for (double& x : z) x /= std::sqrt(var);  // unit variance: a width averaged is the width
        return z;
    }();
    return nodes.data();
}

}  // namespace smokescan
