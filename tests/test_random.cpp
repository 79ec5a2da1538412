// The counter-based random numbers: the ziggurat's normals against the normal distribution.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "normal_cdf.hpp"
#include "smokescan/core/random.hpp"

using namespace smokescan;

namespace {

using smokescan::test::normalCdf;

/// Draws n normals by the ziggurat, each beam-like stream (seed, k) giving 16.
std::vector<double> zigguratDraws(uint64_t seed, size_t n)
{
    std::vector<double> z;
    z.reserve(n);
    for (uint64_t k = 0; z.size() < n; ++k) {
        KeyedRng rng(seed, k);
        for (int j = 0; j < 16 && z.size() < n; ++j) z.push_back(rng.normalZiggurat());
    }
    return z;
}

}  // namespace

TEST(Random, ZigguratNormalsHaveTheNormalDistributionTailsIncluded)
{
    // 4 M draws. Each check would fail for a ziggurat with a wrong layer, a missing wedge test or
    // a truncated tail: the Kolmogorov–Smirnov distance to Φ under its 0.1 % critical value
    // (1.95/√n), a χ² over 64 bins of equal probability, and the counts beyond 3, the tail's
    // start R = 3.4426, 4 and 4.5, on each side, within 4 binomial σ of n·P (beyond 4.5 on one
    // side: 14 expected).
    const size_t n = 4000000;
    std::vector<double> z = zigguratDraws(7, n);
    double sum = 0, sum2 = 0;
    for (double v : z) {
        sum += v;
        sum2 += v * v;
    }
    const double mean = sum / double(n), var = sum2 / double(n) - mean * mean;
    EXPECT_NEAR(mean, 0, 4 / std::sqrt(double(n)));
    EXPECT_NEAR(var, 1, 4 * std::sqrt(2.0 / double(n)));

    std::sort(z.begin(), z.end());
    double ks = 0;
    for (size_t i = 0; i < n; i += 7) {
        const double F = normalCdf(z[i]);
        ks = std::max({ks, std::abs(F - double(i) / double(n)), std::abs(F - double(i + 1) / double(n))});
    }
    EXPECT_LT(ks, 1.95 / std::sqrt(double(n)));

    const int bins = 64;
    std::vector<double> count(bins, 0);
    for (double v : z) count[size_t(std::min(bins - 1, int(normalCdf(v) * bins)))] += 1;
    double chi2 = 0;
    for (double c : count) chi2 += (c - double(n) / bins) * (c - double(n) / bins) / (double(n) / bins);
    EXPECT_LT(chi2, 110.0);  // χ²(63) above 110 has probability 2e-4

    // Each tail on its own (a tail that lost its sign would double one and empty the other).
    for (double t : {3.0, 3.442619855899, 4.0, 4.5}) {
        const double p = normalCdf(-t);
        const double above = double(std::count_if(z.begin(), z.end(), [&](double v) { return v > t; })),
                     below = double(std::count_if(z.begin(), z.end(), [&](double v) { return v < -t; }));
        const double tol = 4 * std::sqrt(double(n) * p * (1 - p)) + 1;
        EXPECT_NEAR(above, double(n) * p, tol) << "above " << t;
        EXPECT_NEAR(below, double(n) * p, tol) << "below " << -t;
    }
    std::printf("ziggurat, %zu draws: mean %.2e, variance %.5f, KS %.2e, chi2(63) %.1f\n", n, mean, var, ks, chi2);
}

TEST(Random, ZigguratNormalsArePureFunctionsOfTheirKeys)
{
    KeyedRng a(3, 11, 2), b(3, 11, 2), c(3, 12, 2);
    for (int i = 0; i < 100; ++i) {
        const double x = a.normalZiggurat();
        EXPECT_EQ(x, b.normalZiggurat());
        EXPECT_NE(x, c.normalZiggurat());
    }
}
