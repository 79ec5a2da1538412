// The parametric bootstrap's pieces (src/fit/fit_bootstrap.hpp): each beam's own threshold, the
// replicates' error counts, the spread of what fitted, and the key the draws hang on.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "fit/fit_bootstrap.hpp"

using namespace smokescan;
using namespace smokescan::detail;

TEST(FitBootstrap, EachBeamsThresholdIsTheMidpointOfItsOwnGapAboutTheMedian)
{
    // Three beams over six scans of falling saturation; beam 0 errs below 0.45, beam 1 below 0.35,
    // beam 2 is noisy (errs at 0.6, reads at 0.3): its errors and readings overlap.
    const std::vector<double> S = {0.7, 0.6, 0.5, 0.4, 0.3, 0.2};
    std::vector<std::vector<bool>> failed;
    for (double s : S) failed.push_back({s < 0.45, s < 0.35, s == 0.6 || s == 0.2});
    const std::vector<double> d = beamThresholdSpread(failed, S);
    ASSERT_EQ(d.size(), 3u);
    // Midpoints 0.45 and 0.35; the median of the separated ones is 0.40.
    EXPECT_NEAR(d[0], 0.05, 1e-12);
    EXPECT_NEAR(d[1], -0.05, 1e-12);
    EXPECT_EQ(d[2], 0.0);
    // Scans outside the camera's span say nothing: without the scan at 0.4 both beams' gaps span
    // 0.3-0.5, and their thresholds coincide.
    std::vector<double> S_gap = S;
    S_gap[3] = NAN;
    const std::vector<double> g = beamThresholdSpread(failed, S_gap);
    EXPECT_NEAR(g[0], 0.0, 1e-12);
    EXPECT_NEAR(g[1], 0.0, 1e-12);
}

TEST(FitBootstrap, ErrorCountsFollowTheModel)
{
    GroupCounts c;
    for (int k = 0; k < 4; ++k) {
        c.t.push_back(k);
        c.n.push_back(4);
        c.e.push_back(-1);
    }
    KeyedRng rng(1, 2);
    // A step with per-beam thresholds 0.5 + {-0.1, 0, 0.1, 0.2}: beams err below their own.
    GroupModel step{0.5, 0.0, false, {-0.1, 0.0, 0.1, 0.2}};
    drawErrorCounts(step, {0.8, 0.55, 0.45, NAN}, rng, c);
    EXPECT_EQ(c.e[0], 0);
    EXPECT_EQ(c.e[1], 2);  // 0.55 < 0.6 and < 0.7
    EXPECT_EQ(c.e[2], 3);
    EXPECT_EQ(c.e[3], -1);  // outside the span: kept
    // A smooth probit: over many scans at S* the beams err half the time, and at S* - 2w 97.7 %.
    GroupModel smooth{0.5, 0.02, false, {}};
    GroupCounts many;
    for (int k = 0; k < 2000; ++k) {
        many.t.push_back(k);
        many.n.push_back(10);
        many.e.push_back(0);
    }
    std::vector<double> at_star(1000, 0.5), below(1000, 0.46);
    at_star.insert(at_star.end(), below.begin(), below.end());
    drawErrorCounts(smooth, at_star, rng, many);
    double half = 0, most = 0;
    for (int k = 0; k < 1000; ++k) half += many.e[size_t(k)];
    for (int k = 1000; k < 2000; ++k) most += many.e[size_t(k)];
    EXPECT_NEAR(half / 10000, 0.5, 4 * std::sqrt(0.25 / 10000));
    EXPECT_NEAR(most / 10000, 0.97725, 4 * std::sqrt(0.977 * 0.023 / 10000));
}

TEST(FitBootstrap, SpreadOfWhatFittedAndAKeyPerRun)
{
    EXPECT_NEAR(finiteSpread({1, 2, 3, NAN, 4}, 3), std::sqrt(5.0 / 3.0), 1e-12);
    EXPECT_TRUE(std::isnan(finiteSpread({1, 2, NAN, NAN}, 3)));  // too few fitted
    const std::vector<double> a = {0.5, 0.4}, b = {0.5, 0.41};
    const std::vector<int> e = {0, 3};
    EXPECT_EQ(dataKey(a, {&e}), dataKey(a, {&e}));
    EXPECT_NE(dataKey(a, {&e}), dataKey(b, {&e}));
    const std::vector<int> e2 = {0, 4};
    EXPECT_NE(dataKey(a, {&e}), dataKey(a, {&e2}));
}
