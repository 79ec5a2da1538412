// The renderer's medium (src/render/render_medium.hpp) against closed forms.
#include <gtest/gtest.h>

#include <cmath>

#include "render/render_medium.hpp"

using namespace smokescan;

// Two smokes overlap with different spectral slopes and phase functions. In an unbounded
// homogeneous medium the first real collision of channel c scatters off component k with
// probability σ_s,k,c / σ_t,c, whatever the tracking; spectral tracking must give each channel that
// share in expectation, E[β_c · 1{k scattered}]. Picking the component by its channel-mean share
// alone (the weight σ_s,c for every component) gives each channel the mean's mix instead: off by
// 10–40 % here.
TEST(RenderMedium, EachChannelScattersOffEachComponentByItsOwnShare)
{
    RenderMedium::Component a, b;
    a.box.extend(Vec3(-1e4, -1e4, -1e4));
    a.box.extend(Vec3(1e4, 1e4, 1e4));
    b.box = a.box;
    a.sigma_t = Rgb(3.0, 2.0, 1.0);
    a.albedo = 0.9;
    a.g = 0.8;
    b.sigma_t = Rgb(0.5, 1.5, 2.5);
    b.albedo = 0.6;
    b.g = -0.3;
    const RenderMedium m({a, b}, 4);
    const Rgb st = a.sigma_t + b.sigma_t;
    const Rgb want_a = a.albedo * a.sigma_t / st, want_b = b.albedo * b.sigma_t / st;
    const int n = 200000;
    Rgb sa = Rgb::Zero(), sb = Rgb::Zero(), sa2 = Rgb::Zero(), sb2 = Rgb::Zero();
    for (int i = 0; i < n; ++i) {
        KeyedRng rng(11, uint64_t(i), 0);
        Rgb beta = Rgb::Ones();
        const MediumEvent ev = m.sample(Ray{Vec3::Zero(), Vec3(0, 0, 1)}, 1e3, beta, rng);
        ASSERT_NE(ev.kind, MediumEvent::Escape);
        if (ev.kind != MediumEvent::Scatter) continue;
        Rgb& s = ev.g == a.g ? sa : sb;
        Rgb& s2 = ev.g == a.g ? sa2 : sb2;
        s += beta;
        s2 += beta * beta;
    }
    for (int c = 0; c < 3; ++c) {
        const double ma = sa[c] / n, mb = sb[c] / n;
        const double ea = std::sqrt((sa2[c] / n - ma * ma) / n), eb = std::sqrt((sb2[c] / n - mb * mb) / n);
        EXPECT_NEAR(ma, want_a[c], 4 * ea + 1e-4) << "component a, channel " << c;
        EXPECT_NEAR(mb, want_b[c], 4 * eb + 1e-4) << "component b, channel " << c;
    }
}
