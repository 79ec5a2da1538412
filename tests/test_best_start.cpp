// The candidate fit's choice of start (src/diagnose/candidate_fit.hpp: bestStart) against the
// full grid's argmin, computed here by brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "../src/diagnose/candidate_fit.hpp"

using smokescan::detail::bestStart;

namespace {

std::vector<double> grid(size_t n)
{
    std::vector<double> g;
    for (size_t i = 0; i < n; ++i) g.push_back(0.25 * double(i) - 12);
    return g;
}

size_t bruteArgmin(const std::vector<double>& g, const std::function<double(double)>& f)
{
    size_t b = 0;
    for (size_t i = 1; i < g.size(); ++i)
        if (f(g[i]) < f(g[b])) b = i;
    return b;
}

}  // namespace

TEST(BestStart, ShortGridsAreSearchedWhole)
{
    // A cost with its minimum at one arbitrary start and noise elsewhere: no structure to exploit.
    for (size_t n : {1, 5, 24}) {
        const std::vector<double> g = grid(n);
        for (size_t m = 0; m < n; ++m) {
            auto f = [&](double t) { return t == g[m] ? -1.0 : std::sin(37 * t) * std::sin(37 * t); };
            EXPECT_EQ(bestStart(g, f), m) << n << " starts, minimum at " << m;
        }
    }
}

TEST(BestStart, OneBasinIsFoundWhereverItsMinimumLiesWhateverTheGridsLength)
{
    // A smooth basin with a camera frame's steps on it (0.1 s): the coarse-to-fine search finds
    // the full grid's argmin for any minimum, at either end, on grids not divisible by the stride.
    for (size_t n : {25, 26, 27, 28, 97}) {
        const std::vector<double> g = grid(n);
        for (double centre = g.front() - 0.1; centre <= g.back() + 0.1; centre += 0.0625) {
            auto f = [&](double t) { return std::pow(t - centre, 2) + 0.05 * std::floor(10 * t) / 10; };
            EXPECT_EQ(bestStart(g, f), bruteArgmin(g, f)) << n << " starts, basin at " << centre;
        }
    }
}

TEST(BestStart, ANarrowBasinBetweenCoarseStartsIsFoundBesideABroaderOne)
{
    // A broad basin at −3.25 s (depth 92, 2 s wide: two coarse starts near −90.6) and a narrow
    // deeper one (0.73 s wide) on any start between coarse ones, 2.5 s or more from it: the
    // narrow one's coarse neighbours rank third and fourth, so refining beside fewer than the three
    // best coarse starts (or every 4th start coarse, the first version) misses it.
    const std::vector<double> g = grid(97);
    int tried = 0;
    for (size_t j = 1; j < g.size(); j += 2) {
        if (std::abs(g[j] + 3.25) < 2.5) continue;
        auto f = [&](double t) {
            return -92 * std::exp(-std::pow((t + 3.25) / 2, 2)) - 100 * std::exp(-std::pow((t - g[j]) / 0.732, 2));
        };
        ASSERT_EQ(bruteArgmin(g, f), j);
        EXPECT_EQ(bestStart(g, f), j) << "narrow basin at " << g[j];
        ++tried;
    }
    EXPECT_GT(tried, 30);
}

TEST(BestStart, NonFiniteCostsNeverWinAndAllNonFiniteCoarseStartsSearchEverything)
{
    const std::vector<double> g = grid(97);
    // Only one start, off the coarse grid, has a finite cost.
    auto one = [&](double t) { return t == g[43] ? 1.0 : NAN; };
    EXPECT_EQ(bestStart(g, one), 43u);
    auto inf = [&](double t) { return t == g[57] ? 3.0 : INFINITY; };
    EXPECT_EQ(bestStart(g, inf), 57u);
    // Every cost infinite: the first start.
    EXPECT_EQ(bestStart(g, [](double) { return INFINITY; }), 0u);
}

TEST(BestStart, ALongGridCostsAtMostSixtyPercentOfItsStarts)
{
    const std::vector<double> g = grid(97);
    int calls = 0;
    bestStart(g, [&](double t) {
        ++calls;
        return t * t;
    });
    EXPECT_LE(calls, 49 + 3 * 3);
    EXPECT_GE(calls, 49);
}
