// The lidar receiver's peak detection (lidar/waveform_peaks.hpp) on waveforms made by hand: a lone
// pulse as the LMS200's run detection reads it, two pulses merged into one run, a pulse on a smoke
// tail that starts in the blind zone, and wiggles that do not stand out.
#include <gtest/gtest.h>

#include <cmath>

#include "smokescan/lidar/waveform_peaks.hpp"

using namespace smokescan;

namespace {

constexpr double kSigma = 0.3;  // the pulse's σ in range [m]

/// A waveform sampled every σ/4 over [0, 20 m] of pulses (range, height) on `base`(r).
template <class Base>
Waveform pulses(const std::vector<std::pair<double, double>>& p, Base base)
{
    Waveform f;
    f.lo = 0;
    f.dr = kSigma / 4;
    f.sig_p = kSigma;
    for (int k = 0; k * f.dr <= 20; ++k) {
        const double r = k * f.dr;
        double w = base(r);
        for (const auto& [at, h] : p) w += h * std::exp(-0.5 * (r - at) * (r - at) / (kSigma * kSigma));
        f.w.push_back(w);
    }
    return f;
}

Waveform pulses(const std::vector<std::pair<double, double>>& p)
{
    return pulses(p, [](double) { return 0.0; });
}

const double kHalfWidth = kSigma * std::sqrt(2 * std::log(2.0));  // a Gaussian's half-maximum from its centre

}  // namespace

TEST(WaveformPeaks, ALonePulseIsTheRunTheLms200sDetectionReads)
{
    // Separate pulses: each its own run, read exactly as waveformEchoes reads it (the 2D sensors'
    // detection), its pedestal 0.
    const Waveform f = pulses({{5.0, 1.0}, {9.03, 0.2}});
    const std::vector<WaveformPeak> p = waveformPeaks(f, 0.01, 0.01);
    const std::vector<WaveformEcho> runs = waveformEchoes(f, 0.01, 8);
    ASSERT_EQ(p.size(), 2u);
    ASSERT_EQ(runs.size(), 2u);
    for (size_t i = 0; i < 2; ++i) {
        EXPECT_TRUE(p[i].opens_run);
        EXPECT_EQ(p[i].pedestal, 0.0);
        EXPECT_EQ(p[i].echo.peak, runs[i].peak);
        EXPECT_EQ(p[i].echo.peak_m, runs[i].peak_m);
        EXPECT_EQ(p[i].echo.lead_m, runs[i].lead_m);
        EXPECT_EQ(p[i].echo.trail_m, runs[i].trail_m);
    }
    // The half-maximum crossings of a sampled Gaussian, linear between samples: within 1 % of σ.
    EXPECT_NEAR(p[1].echo.lead_m, 9.03 - kHalfWidth, 0.01 * kSigma);
    EXPECT_NEAR(p[1].echo.trail_m, 9.03 + kHalfWidth, 0.01 * kSigma);
}

TEST(WaveformPeaks, TwoPulsesInOneRunAreTwoPeaksSplitAtTheirValley)
{
    // 5σ apart, heights 1 and 0.4: one run above 0.01, a valley between them.
    const Waveform f = pulses({{5.0, 1.0}, {5.0 + 5 * kSigma, 0.4}});
    ASSERT_EQ(waveformEchoes(f, 0.01, 8).size(), 1u);  // the LMS200 reads one run
    const std::vector<WaveformPeak> p = waveformPeaks(f, 0.01, 0.01);
    ASSERT_EQ(p.size(), 2u);
    EXPECT_TRUE(p[0].opens_run);
    EXPECT_FALSE(p[1].opens_run);
    EXPECT_NEAR(p[0].echo.peak_m, 5.0, f.dr / 2);
    EXPECT_NEAR(p[1].echo.peak_m, 5.0 + 5 * kSigma, f.dr / 2);
    // The valley: the lowest sample between them, and the fall to it from the first peak.
    size_t kv = 0;
    for (size_t k = 0; k < f.w.size(); ++k)
        if (k * f.dr > 5.0 && k * f.dr < 5.0 + 5 * kSigma && (kv == 0 || f.w[k] < f.w[kv])) kv = k;
    EXPECT_EQ(p[1].pedestal, f.w[kv]);
    EXPECT_EQ(p[1].fall, p[0].echo.peak - f.w[kv]);
    EXPECT_EQ(p[1].first_sample, int(kv));
    // The second's leading crossing: where the two pulses' sum is half-way from the valley to its
    // peak (bisection on the closed form), within 1 % of σ (linear between samples). The valley
    // is the other pulse's tail there, not under the peak: the crossing lies 0.13 σ later than the
    // pulse's own half maximum.
    const double c2 = 5.0 + 5 * kSigma, half = f.w[kv] + 0.5 * (p[1].echo.peak - f.w[kv]);
    const auto sum = [&](double r) {
        return std::exp(-0.5 * std::pow((r - 5.0) / kSigma, 2)) + 0.4 * std::exp(-0.5 * std::pow((r - c2) / kSigma, 2));
    };
    double lo = c2 - 2 * kSigma, hi = c2;
    for (int i = 0; i < 60; ++i) (sum(0.5 * (lo + hi)) < half ? lo : hi) = 0.5 * (lo + hi);
    EXPECT_NEAR(p[1].echo.lead_m, lo, 0.01 * kSigma);
    EXPECT_NEAR(p[1].echo.lead_m - (c2 - kHalfWidth), 0.13 * kSigma, 0.02 * kSigma);
    // The first peak's trailing crossing is looked for up to the valley, not past it.
    EXPECT_LE(p[0].echo.trail_m, (p[1].first_sample) * f.dr);
}

TEST(WaveformPeaks, APulseOnASmokeTailFromTheFirstSampleRisesOutOfIt)
{
    // The near field's smoke: a tail from the first sample, falling as 1/r² past 0.3 m; a wall's
    // pulse at 4 m on it, 20 times the tail's level there.
    const auto tail = [](double r) { return 0.5 * std::min(1.0, 0.09 / (r * r + 1e-12)); };
    const double h = 20 * tail(4.0);
    const Waveform f = pulses({{4.0, h}}, tail);
    const std::vector<WaveformPeak> p = waveformPeaks(f, 1e-4, 1e-4);
    ASSERT_GE(p.size(), 2u);
    EXPECT_TRUE(p[0].opens_run);
    EXPECT_EQ(p[0].first_sample, 0);
    const WaveformPeak& wall = p[1];
    EXPECT_FALSE(wall.opens_run);
    EXPECT_NEAR(wall.echo.peak_m, 4.0, f.dr / 2);
    // Its height over the valley is the pulse's less the tail's fall across half a pulse: 5 %.
    EXPECT_NEAR(wall.echo.peak - wall.pedestal, h, 0.05 * h);
    EXPECT_NEAR(wall.echo.lead_m, 4.0 - kHalfWidth, 0.05 * kSigma);
}

TEST(WaveformPeaks, WigglesThatDoNotStandOutByTheProminenceDoNotSplit)
{
    // A pulse on a plateau with a ripple of 0.7 × the prominence on it 8 σ later, and one of
    // 1.5 ×: only the second splits the run.
    const double prom = 0.05;
    const auto plateau4to10 = [](double r) { return r > 4 && r < 10 ? 0.1 : 0.0; };
    const Waveform small = pulses({{5.0, 1.0}, {5.0 + 8 * kSigma, 0.7 * prom}}, plateau4to10);
    const Waveform large = pulses({{5.0, 1.0}, {5.0 + 8 * kSigma, 1.5 * prom}}, plateau4to10);
    EXPECT_EQ(waveformPeaks(small, 0.01, prom).size(), 1u);
    EXPECT_EQ(waveformPeaks(large, 0.01, prom).size(), 2u);
    // Without any valley below the threshold the run is one echo however long it is.
    const Waveform plateau = pulses({}, [](double r) { return r > 2 && r < 12 ? 0.3 : 0.0; });
    ASSERT_EQ(waveformPeaks(plateau, 0.01, prom).size(), 1u);
    EXPECT_TRUE(waveformPeaks(plateau, 0.5, prom).empty());
}

TEST(WaveformPeaks, AValleyBelowTheThresholdEndsTheRunAndAZeroProminenceIsRefused)
{
    // Two pulses whose valley dips under the threshold: two runs, each peak a run's first, the
    // second read from zero (its half-height at half its peak, not half-way up from the valley).
    const Waveform f = pulses({{5.0, 1.0}, {5.0 + 5 * kSigma, 0.4}});
    const std::vector<WaveformPeak> p = waveformPeaks(f, 0.2, 0.01);
    ASSERT_EQ(p.size(), 2u);
    EXPECT_TRUE(p[1].opens_run);
    EXPECT_EQ(p[1].pedestal, 0.0);
    // A peak on the last sample is read there.
    Waveform edge = pulses({{20.0, 1.0}});
    const std::vector<WaveformPeak> last = waveformPeaks(edge, 0.1, 0.1);
    ASSERT_EQ(last.size(), 1u);
    EXPECT_EQ(last[0].echo.peak_m, edge.lo + double(edge.w.size() - 1) * edge.dr);
    EXPECT_THROW(waveformPeaks(f, 0.0, 0.0), std::invalid_argument);
    EXPECT_TRUE(waveformPeaks(Waveform{}, 0.1, 0.1).empty());
}
