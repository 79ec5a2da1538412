// The diagnosis' sign-flip test (src/diagnose/sign_flip.hpp) against its exact distribution, and
// its size under the null over many independent draws.
#include <gtest/gtest.h>

#include <cmath>

#include "../src/diagnose/sign_flip.hpp"
#include "smokescan/core/random.hpp"

using smokescan::KeyedRng;
using smokescan::detail::signFlipP;

TEST(SignFlip, ExactSmallCases)
{
    // n positive gains: only the observed signs reach the total, p = 2^−n.
    EXPECT_DOUBLE_EQ(signFlipP({1, 2, 3, 4, 5}, 0, 1), 1.0 / 32);
    // Zeros do not count as units.
    EXPECT_DOUBLE_EQ(signFlipP({1, 0, 2, 0, 3}, 0, 1), 1.0 / 8);
    // Gains {3, −1, −1}, total 1. The eight flips sum to 5, 3, 3, 1 (with +3) and −1, −3, −3, −5
    // (with −3): four of eight reach 1.
    EXPECT_DOUBLE_EQ(signFlipP({3, -1, -1}, 0, 1), 4.0 / 8);
    // All negative: every flip reaches the total, p = 1.
    EXPECT_DOUBLE_EQ(signFlipP({-1, -2, -3}, 0, 1), 1.0);
    EXPECT_DOUBLE_EQ(signFlipP({}, 0, 1), 1.0);
}

TEST(SignFlip, MonteCarloMatchesTheExactValue)
{
    // 24 units (beyond exact enumeration): the binomial tail of sign counts for equal gains.
    // With 24 equal gains g and the observed 18 positive, the sum reaches it when at least 18 of 24
    // flips are positive: P(X ≥ 18), X ~ Bin(24, 1/2).
    std::vector<double> g(24, 1.0);
    for (int i = 0; i < 6; ++i) g[size_t(i)] = -1.0;
    double exact = 0;
    for (int k = 18; k <= 24; ++k)
        exact += std::exp(std::lgamma(25) - std::lgamma(k + 1) - std::lgamma(25 - k)) / (1 << 24);
    const long long flips = 200000;
    const double p = signFlipP(g, flips, 7);
    EXPECT_NEAR(p, exact, 4 * std::sqrt(exact * (1 - exact) / flips) + 1e-5) << "exact " << exact;
}

TEST(SignFlip, SizeUnderTheNullIsItsLevel)
{
    // Symmetric gains of unequal sizes: P(p ≤ α) ≤ α, and close to it (the test is exact up to
    // ties), at α = 0.05 and 0.01 over 4000 draws of 12 units.
    int hit05 = 0, hit01 = 0;
    const int n = 4000;
    for (int d = 0; d < n; ++d) {
        KeyedRng rng(99, uint64_t(d));
        std::vector<double> g;
        for (int i = 0; i < 12; ++i) g.push_back(rng.normal() * (1 + 3 * rng.uniform()));
        const double p = signFlipP(g, 0, 1);
        hit05 += p <= 0.05;
        hit01 += p <= 0.01;
    }
    EXPECT_NEAR(double(hit05) / n, 0.05, 4 * std::sqrt(0.05 * 0.95 / n));
    EXPECT_NEAR(double(hit01) / n, 0.01, 4 * std::sqrt(0.01 * 0.99 / n));
}
