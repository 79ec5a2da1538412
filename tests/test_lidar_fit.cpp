// A 3D lidar's surfaces' reflectance factors from its recorded intensities (fit/lidar_fit.hpp):
// the residual; the fit on drawn samples (unit pulls, the scatter, the beams it uses); on
// simulated frames (the scene's own reflectances come out as 1 and the receiver's noise as the
// preset's, a darker wall as its ratio, a glossy one as a misfit); and the factor's held-out gain
// on what the fit never reads, the detections.
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numeric>

#include "error_of.hpp"
#include "fit/intensity_ratio_residual.hpp"
#include "scratch.hpp"
#include "smokescan/core/random.hpp"
#include "smokescan/diagnose/lidar_diagnosis.hpp"
#include "smokescan/fit/lidar_fit.hpp"
#include "smokescan/lidar/point_cloud_io.hpp"
#include "smokescan/pipeline/lidar_diagnose_run.hpp"
#include "smokescan/pipeline/lidar_fit_run.hpp"
#include "smokescan/scene/scene_io.hpp"

using namespace smokescan;
using smokescan::test::errorOf;
using smokescan::test::scratch;

namespace {

double mean(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / double(v.size()); }
double sd(const std::vector<double>& v)
{
    const double m = mean(v);
    double s = 0;
    for (double x : v) s += (x - m) * (x - m);
    return std::sqrt(s / double(v.size() - 1));
}

/// Frames of a VLP-16 in `scene` from t0 (seed: the receiver's noise).
std::vector<LidarFrame> simulate(const Scene& scene, double t0, int frames, uint64_t seed = 7)
{
    LidarRunConfig c;
    c.sensor = "vlp16";
    c.from_s = t0;
    c.to_s = t0 + 0.1 * frames - 0.05;
    c.seed = seed;
    return LidarRun(scene, c).collect();
}

/// `frames` replayed in the factory's smoke by the VLP-16 and tallied.
LidarTally tallyInFactory(const std::vector<LidarFrame>& frames)
{
    static const Scene scene = loadScene("factory_smoke");
    LidarRunConfig c;
    c.sensor = "vlp16";
    c.from_s = frames.front().start_s;
    const LidarRun run(scene, c);
    LidarTally t(run.scanner().pattern(), run.spec().channels(), returnTolerance_m(run.spec()));
    t.keepIntensities(true);
    for (size_t k = 0; k < frames.size(); ++k)
        t.add(run.scanner().expected(frames[k].start_s, true), frames[k].points, int(k % 2));
    return t;
}

/// The factory with `surface` in a material of its own, `change` applied to it.
Scene factoryWith(const std::string& surface, const std::function<void(Material&)>& change)
{
    Scene s = loadScene("factory_smoke");
    for (Surface& sf : s.surfaces)
        if (sf.name == surface) {
            Material m = s.materials[size_t(sf.material)];
            m.name += "_changed";
            change(m);
            s.materials.push_back(m);
            sf.material = int(s.materials.size() - 1);
            return s;
        }
    ADD_FAILURE() << "no surface " << surface;
    return s;
}

const SurfaceReflectanceFit& fitOf(const LidarFitResult& r, const Scene& scene, const std::string& name)
{
    for (const SurfaceReflectanceFit& f : r.surfaces)
        if (scene.surfaces[size_t(f.surface)].name == name) return f;
    static const SurfaceReflectanceFit none;
    ADD_FAILURE() << "no fit of " << name;
    return none;
}

double totalSe(const SurfaceReflectanceFit& f) { return std::hypot(f.factor_se, f.factor_sys); }

constexpr double kRangeSd = 0.015;  // the VLP-16 preset's range_sigma_m

}  // namespace

TEST(IntensityRatioResidual, IsThePeaksMissInItsNoiseSdOnTheReplaysParabolaThroughItsDimmerPeaks)
{
    // The replay's 40 reads 0.6 of itself at half the surface's power and 0.35 at a quarter.
    LidarIntensitySample x;
    x.expected = 40, x.at_half = 0.6f, x.at_quarter = 0.35f;
    const detail::IntensityRatioResidual r(30, x, 2);
    auto at = [&](double k) {
        const ceres::Jet<double, 1> kj(k, 0);
        ceres::Jet<double, 1> out;
        EXPECT_TRUE(r(&kj, &out));
        return out;
    };
    // Through the three nodes: (30 − 40·g)/2.
    EXPECT_NEAR(at(1).a, (30 - 40) / 2.0, 1e-6);
    EXPECT_NEAR(at(0.5).a, (30 - 40 * 0.6) / 2.0, 1e-6);
    EXPECT_NEAR(at(0.25).a, (30 - 40 * 0.35) / 2.0, 1e-6);
    // Between them the parabola g(k) = a + b·k + c·k² through them: c = −4/15, b = 1.2, a = 1/15.
    const double c = -4.0 / 15, b = 1.2, a = 1 - b - c;
    for (double k : {0.3, 0.6, 0.9}) EXPECT_NEAR(at(k).a, (30 - 40 * (a + b * k + c * k * k)) / 2.0, 1e-5) << k;
    EXPECT_NEAR(at(0.6).v[0], -40 * (b + 2 * c * 0.6) / 2.0, 1e-5);
    // Beyond the ends, its tangents: slope b + 2c at 1, b + c/2 at ¼.
    EXPECT_NEAR(at(1.5).a, (30 - 40 * (1 + 0.5 * (b + 2 * c))) / 2.0, 1e-5);
    EXPECT_NEAR(at(0.05).a, (30 - 40 * (0.35 - 0.2 * (b + 0.5 * c))) / 2.0, 1e-5);
    // An echo alone (½ at half, ¼ at a quarter) reads k times itself at any k.
    x.at_half = 0.5f, x.at_quarter = 0.25f;
    for (double k : {0.1, 0.3, 0.7, 1.0, 2.5}) EXPECT_NEAR(x.scaleAt(k), k, 1e-6) << k;
}

TEST(LidarFit, DrawnIntensitiesGiveTheirFactorsWithUnitPullsAndTheReceiversScatter)
{
    // Three surfaces at factors 0.5, 1 and 1.7 and a fourth with too few beams; a receiver 1.3
    // times as noisy as the preset says; smoke under some echoes (a share of the peak that does
    // not scale, down to 0.3: those under half are left out); one beam in 200 a faint echo taken
    // instead (2 % of the intensity). Drawn as the recorder's intensity is made: the peak with its
    // noise, times R²/O(R) at the range read with its own noise.
    const double k_true[3] = {0.5, 1.0, 1.7}, noisier = 1.3;
    std::vector<double> pulls[3], scatters, scatter_ses;
    for (uint64_t seed = 1; seed <= 200; ++seed) {
        KeyedRng rng(4242, seed);
        std::vector<LidarIntensitySample> s;
        long long usable[4] = {0, 0, 0, 0};
        for (int surface = 0; surface < 4; ++surface)
            for (int i = 0; i < (surface < 3 ? 400 : 20); ++i) {
                const double k = k_true[std::min(surface, 2)];
                LidarIntensitySample x;
                x.surface = surface;
                x.peak_sd = float(std::exp(std::log(20.0) + rng.uniform() * std::log(5000 / 20.0)));
                x.range_m = float(2 + 38 * rng.uniform());
                x.expected = float(1 + 109 * rng.uniform());
                // Smoke under the echo: a share of its peak that stays when the surface dims.
                const double smoke = rng.uniform() < 0.7 ? 0.0 : 0.7 * rng.uniform();
                x.at_half = float(smoke + (1 - smoke) * 0.5);
                x.at_quarter = float(smoke + (1 - smoke) * 0.25);
                x.peak_noise = float(1 + 0.5 * rng.uniform());
                const double at_k = x.expected * (smoke + (1 - smoke) * k);
                const double peak = at_k + noisier * x.expected * x.peak_noise / x.peak_sd * rng.normal();
                x.recorded_range_m = float(x.range_m + kRangeSd * rng.normal());
                const double r = double(x.recorded_range_m) / x.range_m;
                x.recorded = float(peak * r * r);
                const bool faint = rng.uniform() < 0.005;
                if (faint) x.recorded = float(0.02 * x.recorded);
                if (!faint && 1 - smoke >= 0.5 - 1e-6 && x.peak_sd * at_k / x.expected >= 50 && at_k <= 200)
                    ++usable[surface];
                s.push_back(x);
            }
        const LidarFitResult r = fitLidarIntensities(s);
        ASSERT_EQ(r.surfaces.size(), 4u);
        EXPECT_FALSE(r.surfaces[3].fitted);
        for (int surface = 0; surface < 3; ++surface) {
            const SurfaceReflectanceFit& f = r.surfaces[size_t(surface)];
            ASSERT_TRUE(f.fitted);
            // Exactly the beams bright enough at the factor and mostly the surface's, none of the
            // faint echoes.
            if (seed <= 20) EXPECT_EQ(f.beams, usable[surface]) << surface << " seed " << seed;
            pulls[surface].push_back((f.factor - k_true[surface]) / f.factor_se);
            EXPECT_NEAR(f.factor_sys, kIntensitySystematic * f.factor, 1e-12);
        }
        scatters.push_back(r.scatter);
        scatter_ses.push_back(r.scatter_se);
    }
    for (int surface = 0; surface < 3; ++surface) {
        std::printf("factor %.1f: pulls mean %.3f sd %.3f\n", k_true[surface], mean(pulls[surface]),
                    sd(pulls[surface]));
        EXPECT_NEAR(mean(pulls[surface]), 0, 0.25);  // 3.5 × 1/√200
        EXPECT_NEAR(sd(pulls[surface]), 1, 0.15);  // 3 × 1/√400
    }
    std::printf("scatter mean %.4f (drawn %.1f), sd %.4f against its se %.4f\n", mean(scatters), noisier, sd(scatters),
                mean(scatter_ses));
    EXPECT_NEAR(mean(scatters), noisier, 0.01);
    EXPECT_NEAR(sd(scatters) / mean(scatter_ses), 1, 0.2);
}

TEST(LidarFit, NoSurfaceWithEnoughBrightBeamsIsAnError)
{
    std::vector<LidarIntensitySample> s(100, LidarIntensitySample{0, 10, 5, 10, 5, 20});  // peaks 20 sd: too faint
    const std::string e = errorOf([&] { fitLidarIntensities(s); });
    EXPECT_NE(e.find("no surface has 30 answered beams"), std::string::npos) << e;
    EXPECT_NE(errorOf([&] { fitLidarIntensities({}); }).find("no surface"), std::string::npos);
}

TEST(LidarFit, TheScenesOwnReflectancesComeOutAsOneAndTheReceiversNoiseAsThePresets)
{
    // Two frames of the factory in its thin smoke at 20 s against their own replay: every surface
    // fitted reads the scene's reflectance, the intensities scatter as the receiver's noise says,
    // the ranges as the preset's range_sigma_m.
    const Scene scene = loadScene("factory_smoke");
    const LidarTally t = tallyInFactory(simulate(scene, 20, 2));
    const LidarFitResult r = fitLidarIntensities(t.intensities());
    int fitted = 0;
    for (const SurfaceReflectanceFit& f : r.surfaces) {
        if (!f.fitted) continue;
        ++fitted;
        EXPECT_NEAR(f.factor, 1, 4 * totalSe(f)) << scene.surfaces[size_t(f.surface)].name;
        EXPECT_NEAR(f.scatter, 1, 0.1) << scene.surfaces[size_t(f.surface)].name;
    }
    EXPECT_GE(fitted, 8);
    EXPECT_GT(r.beams, 40000);
    EXPECT_NEAR(r.scatter, 1, 4 * r.scatter_se + 0.01);
}

TEST(LidarFit, ADarkerWallIsFittedAsItsRatioAndAGlossyOneShowsAsAMisfit)
{
    // Planted as the recorded room's material: wall_north's NIR reflectance 0.4 where the scene
    // says 0.7 (the factor 4/7); then a wall as bright but glossy (specular 0.4, roughness 0.3),
    // whose echo is not any factor times a Lambertian one: its brightness follows the angle.
    const Scene darker = factoryWith("wall_north", [](Material& m) { m.nir_785 = m.nir_905 = 0.4; });
    const LidarFitResult r = fitLidarIntensities(tallyInFactory(simulate(darker, 20, 2)).intensities());
    const SurfaceReflectanceFit& dark = fitOf(r, darker, "wall_north");
    std::printf("darker wall: %.5f +/- %.2g (stat) +/- %.2g (sys), %lld beams, scatter %.3f\n", dark.factor,
                dark.factor_se, dark.factor_sys, dark.beams, dark.scatter);
    EXPECT_NEAR(dark.factor, 0.4 / 0.7, 4 * totalSe(dark));
    // Beams whose echo dims into the smoke's run at that factor read √2 noisier than their replay
    // (a valley's sample besides the peak's): a scatter a little over 1.
    EXPECT_LT(dark.scatter, 1.3);
    EXPECT_GT(dark.beams, 2000);
    for (const char* other : {"floor", "wall_east", "partition"})
        EXPECT_NEAR(fitOf(r, darker, other).factor, 1, 4 * totalSe(fitOf(r, darker, other))) << other;

    const Scene glossy = factoryWith("wall_north", [](Material& m) { m.specular = 0.4, m.roughness = 0.3; });
    const LidarFitResult g = fitLidarIntensities(tallyInFactory(simulate(glossy, 20, 2)).intensities());
    const SurfaceReflectanceFit& gl = fitOf(g, glossy, "wall_north");
    std::printf("glossy wall: %.5f +/- %.2g, scatter %.2f\n", gl.factor, gl.factor_se, gl.scatter);
    EXPECT_GT(gl.scatter, 3);  // the misfit shows, and widens its error with it
    EXPECT_GT(gl.factor_se, 3 * dark.factor_se);
}

namespace {

/// Frames written as `smokescan scan --points` writes them.
std::string writeFrames(const std::string& name, const std::vector<LidarFrame>& frames)
{
    const std::filesystem::path dir = scratch("lidar_fit_" + name);
    std::ofstream index(dir / "frames.csv");
    index << frameIndexHeader();
    for (const LidarFrame& f : frames) {
        const std::string file = std::to_string(f.index) + ".pcd";
        writePcd((dir / file).string(), f);
        index << frameIndexRow(f, file);
    }
    return dir.string();
}

const LidarFinding& thresholdOf(const LidarDiagnosis& d)
{
    for (const LidarFinding& f : d.tried)
        if (f.cause == LidarCause::SurfaceThreshold) return f;
    static const LidarFinding none;
    ADD_FAILURE() << "no surface threshold tried";
    return none;
}

}  // namespace

TEST(LidarFitRun, TheFittedFactorExplainsHeldOutDetectionsTheFitNeverReads)
{
    // The recorded room's surface seen most through the smoke at 38 s reflects 30 % of what the
    // scene says. The fit reads only the intensities of the beams the replay is sure of; the
    // diagnosis's surface threshold reads whether the uncertain beams in the smoke return at all.
    // Fitted on frames at 38 s, the factor must explain other frames' detections at 41 s.
    const Scene scene = loadScene("factory_smoke");
    const LidarDiagnosis clean = diagnoseLidar(tallyInFactory(simulate(scene, 38, 2)), kRangeSd);
    int surface = -1;
    long long most = 0;
    for (const auto& [sf, o] : clean.surfaces)
        if (o.beams > most) most = o.beams, surface = sf;
    ASSERT_GE(surface, 0);
    const std::string name = scene.surfaces[size_t(surface)].name;
    const Scene dark = factoryWith(name, [](Material& m) { m.nir_785 *= 0.3, m.nir_905 *= 0.3; });

    LidarFitRunConfig fc;
    fc.frames.scene = "factory_smoke";
    fc.frames.points = writeFrames("search", simulate(dark, 38, 4));
    fc.frames.sensor.sensor = "vlp16";
    const LidarFitRunResult fit = runLidarFit(fc);
    const SurfaceReflectanceFit& f = fitOf(fit.fit, scene, name);
    std::printf("%s: factor %.4f +/- %.2g (stat) +/- %.2g (sys), %lld beams\n", name.c_str(), f.factor, f.factor_se,
                f.factor_sys, f.beams);
    EXPECT_NEAR(f.factor, 0.3, 4 * totalSe(f));
    const std::string preset = (scratch("lidar_fit_preset") / "lidar.toml").string();
    std::ofstream(preset) << fit.preset;
    const long fitted = std::count_if(fit.fit.surfaces.begin(), fit.fit.surfaces.end(),
                                      [](const SurfaceReflectanceFit& x) { return x.fitted; });
    EXPECT_EQ(long(lidarSpec(preset).extensions.surfaces.size()), fitted);

    LidarDiagnoseRunConfig dc;
    dc.scene = "factory_smoke";
    dc.points = writeFrames("heldout", simulate(dark, 41, 6, 8));
    dc.sensor.sensor = "vlp16";
    const LidarDiagnosis before = runLidarDiagnosis(dc).diagnosis;
    dc.sensor.sensor = preset;
    const LidarDiagnosis after = runLidarDiagnosis(dc).diagnosis;
    const LidarFinding &t0 = thresholdOf(before), &t1 = thresholdOf(after);
    std::printf("held out, preset: %s (%s %+.3f, %.0f nats); fitted: %s (%s %+.3f, %.0f nats)\n",
                before.verdict.c_str(), t0.surface >= 0 ? scene.surfaces[size_t(t0.surface)].name.c_str() : "-",
                t0.effect, t0.gain_nats, after.verdict.c_str(),
                t1.surface >= 0 ? scene.surfaces[size_t(t1.surface)].name.c_str() : "-", t1.effect, t1.gain_nats);
    EXPECT_TRUE(t0.named);
    EXPECT_EQ(t0.surface, surface);
    EXPECT_EQ(before.verdict, "surface_threshold");
    EXPECT_EQ(after.verdict, "none");
    EXPECT_FALSE(t1.named && t1.surface == surface);
    EXPECT_LT(t1.gain_nats, 0.05 * t0.gain_nats);
}
