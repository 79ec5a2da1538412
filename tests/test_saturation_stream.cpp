// The camera's stream of a simulated run: target saturation predicted through the calibration curve
// or measured in rendered frames. Rendered frames of the BOCAS run must measure what the calibration
// measured at the same density; the stream's noise, patches and clock are checked statistically.
#include <gtest/gtest.h>

#include "sanitized.hpp"

#include <cmath>

#include "smokescan/calib/calibration.hpp"
#include "smokescan/calib/saturation_predict.hpp"
#include "smokescan/camera/saturation_render.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/scene/scene_io.hpp"

using namespace smokescan;

// BOCAS's room smoke is one homogeneous box, so a frame at scene time t shows the target through
// homogeneous smoke of density ρ(t) = column / path; calibrate() renders the room filled with
// exactly that density. Same frame size and spp, different seeds: the two measurements must agree
// within their errors (the camera's noise and the converged field's).
TEST(SaturationStream, RenderedFramesMeasureWhatTheCalibrationMeasured)
{
    if (test::sanitized()) GTEST_SKIP() << "converged frames compared within their errors: the Release build";
    const Scene scene = loadScene("bocas");
    const SurfaceSet surfaces(scene);
    const SaturationPredictor geometry(scene, surfaces, readCalibrationJson("bocas").curve);  // column, path
    SaturationRenderConfig rc;
    rc.width = 160;
    rc.height = 120;
    rc.seed = 11;
    const SaturationRenderer renderer(scene, surfaces, rc);
    const std::vector<double> times = {10.0, 40.0, 300.0, 130.0};  // clear, thin, at the threshold, densest
    CalibrateConfig cc;
    cc.width = rc.width;
    cc.height = rc.height;
    cc.seed = 3;
    cc.densities.clear();
    for (double t : times) cc.densities.push_back(geometry.density(SmokeField::at(scene.volumes, t)));
    EXPECT_EQ(cc.densities[0], 0.0);
    for (size_t k = 1; k < times.size(); ++k) ASSERT_GT(cc.densities[k], cc.densities[k - 1]);
    const CalibrationResult cal = calibrate(scene, cc);
    // The curve fitted to these same points, printed beside them (a check of it against them would
    // be circular; Cli.ScanSaturationFromRenderedFrames predicts through an independent calibration).
    const SaturationPredictor predictor(scene, surfaces, cal.fit.curve);
    double prev = 1;
    for (size_t k = 0; k < times.size(); ++k) {
        const TargetSaturation m = renderer.measure(times[k], k);
        const SaturationPoint& c = cal.points[k];
        const double se_r = m.se;
        const double tol = 4 * std::hypot(se_r, c.sigma);
        std::printf("t = %5.0f s  rho = %.5f  rendered %.4f ± %.4f  calibration %.4f ± %.4f  predicted %.4f\n",
                    times[k], c.density, m.all.mean, se_r, c.saturation, c.sigma,
                    predictor.saturation(SmokeField::at(scene.volumes, times[k])));
        EXPECT_NEAR(m.all.mean, c.saturation, tol) << "t = " << times[k];
        EXPECT_LT(m.all.mean, prev) << "saturation must fall as the smoke thickens";
        prev = m.all.mean;
        EXPECT_EQ(m.patches.size(), 3u);  // blue, gold, yellow
        EXPECT_GT(m.exposure, 0);
    }
}

// The stream around any frame source: frame times on the scene clock, written on the camera's;
// Gaussian noise of the configured σ per column (mean within 3σ/√N, sample σ within 3 of its
// standard errors), independent between columns; clamped to [0, 1]; a pure function of the seed.
TEST(SaturationStream, NoisePatchesAndClockPerColumn)
{
    int calls = 0;
    const SaturationFrameFn frame = [&](double t, uint64_t k) {
        ++calls;
        EXPECT_NEAR(t, 5.0 + 0.5 * double(k), 1e-9);
        return SaturationFrame{0.5, {{"blue", 0.3}, {"black", 0.0}}};
    };
    SaturationSimConfig cfg;
    cfg.from_s = 5;
    cfg.to_s = 5 + 0.5 * 3999;
    cfg.rate_hz = 2;
    cfg.sigma = 0.02;
    cfg.clock_offset_s = -1.5;
    cfg.seed = 9;
    const SaturationSeries s = simulateSaturation(frame, cfg);
    ASSERT_EQ(s.time_s.size(), 4000u);
    EXPECT_EQ(calls, 4000);
    EXPECT_NEAR(s.time_s.front(), 3.5, 1e-12);
    ASSERT_EQ(s.patch_names, (std::vector<std::string>{"black", "blue"}));
    const double n = double(s.time_s.size());
    auto moments = [&](const std::vector<double>& v, double mu0) {
        double m = 0, q = 0;
        for (double x : v) m += x;
        m /= n;
        for (double x : v) q += (x - m) * (x - m);
        const double sd = std::sqrt(q / (n - 1));
        EXPECT_NEAR(m, mu0, 3 * cfg.sigma / std::sqrt(n));
        EXPECT_NEAR(sd, cfg.sigma, 3 * cfg.sigma / std::sqrt(2 * (n - 1)));
    };
    moments(s.saturation, 0.5);
    moments(s.patch[1], 0.3);
    double r = 0;  // correlation of the two unclamped columns' noise
    for (size_t k = 0; k < s.saturation.size(); ++k) r += (s.saturation[k] - 0.5) * (s.patch[1][k] - 0.3);
    EXPECT_LT(std::abs(r / (n * cfg.sigma * cfg.sigma)), 4 / std::sqrt(n));
    int at_zero = 0;  // the black patch: noise about 0, clamped
    for (double x : s.patch[0]) {
        EXPECT_GE(x, 0.0);
        at_zero += x == 0.0;
    }
    EXPECT_NEAR(at_zero / n, 0.5, 3 * 0.5 / std::sqrt(n));
    EXPECT_EQ(simulateSaturation(frame, cfg).saturation, s.saturation);

    // A frame that lost a patch the first one had is an error, not a ragged table.
    const SaturationFrameFn losing = [](double, uint64_t k) {
        SaturationFrame f{0.5, {{"blue", 0.3}}};
        if (k == 2) f.patches.clear();
        return f;
    };
    EXPECT_THROW(simulateSaturation(losing, cfg), Error);
    cfg.rate_hz = 0;
    EXPECT_THROW(simulateSaturation(frame, cfg), Error);
}

// A camera that does not see the target fails when the renderer is made, not after the scans.
TEST(SaturationStream, RendererRefusesACameraThatMissesTheTarget)
{
    Scene scene = loadScene("bocas");
    const SurfaceSet surfaces(scene);
    SaturationRenderConfig small;
    small.width = 80;
    small.height = 60;
    EXPECT_NO_THROW(SaturationRenderer(scene, surfaces, small));
    scene.cameras[0].pose.R =
        scene.cameras[0].pose.R * Pose::fromRpyDeg(Vec3::Zero(), Vec3(0, 0, 180)).R;  // facing away
    EXPECT_THROW(SaturationRenderer(scene, surfaces, small), Error);
    small.field.batch_spp = 0;
    EXPECT_THROW(SaturationRenderer(scene, surfaces, small), Error);
    small = {};
    small.camera = "nobody";
    EXPECT_THROW(SaturationRenderer(scene, surfaces, small), Error);
}

// The target's patches, as both the renderer and `saturation --ids` find them from object ids.
TEST(SaturationStream, TargetPatchesComeFromSurfaceNames)
{
    const Scene scene = loadScene("bocas");
    const TargetPatches t = targetPatches(scene, "target_");
    EXPECT_EQ(t.names, (std::vector<std::string>{"blue", "yellow", "gold"}));
    ASSERT_EQ(t.patch_of.size(), scene.surfaces.size());
    for (size_t i = 0; i < scene.surfaces.size(); ++i) {
        const std::string& n = scene.surfaces[i].name;
        if (n.rfind("target_", 0) == 0)
            EXPECT_EQ("target_" + t.names.at(size_t(t.of(int(i)))), n);
        else
            EXPECT_EQ(t.of(int(i)), -1) << n;
    }
    EXPECT_EQ(t.of(-1), -1);  // background pixels
    EXPECT_EQ(t.of(int(scene.surfaces.size())), -1);
    try {
        targetPatches(scene, "poster_");
        FAIL() << "a prefix no surface has must be refused";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("poster_*"), std::string::npos) << e.what();
    }
}

// The predictor measures along its line of sight to each target patch it sees: two targets apart
// (their mean between them, on nothing) are both measured; a patch another surface hides is left
// out; a camera that sees none is refused. The smoke is a box over half the room, so the lines'
// densities differ and their mean is checked against each line's own column.
TEST(SaturationStream, ThePredictorMeasuresEachTargetPatchItSees)
{
    auto sceneWith = [](const std::string& extra, const std::string& look_at = "[3.0, 0.0, 0.6]") {
        const std::string text = std::string(
                                     "[scene]\nname = \"apart\"\n"
                                     "[[materials]]\nname = \"paper\"\nalbedo = [0.8, 0.1, 0.1]\n"
                                     "[[surfaces]]\nname = \"target_left\"\nmaterial = \"paper\"\ntype = \"quad\"\n"
                                     "corner = [3.0, 0.6, 0.2]\nu = [0.0, 0.3, 0.0]\nv = [0.0, 0.0, 0.8]\n"
                                     "[[surfaces]]\nname = \"target_right\"\nmaterial = \"paper\"\ntype = \"quad\"\n"
                                     "corner = [3.0, -0.9, 0.2]\nu = [0.0, 0.3, 0.0]\nv = [0.0, 0.0, 0.8]\n"
                                     "[[cameras]]\nname = \"cam\"\nposition = [0.0, 0.0, 0.6]\n"
                                     "look_at = " +
                                     look_at +
                                     "\n"
                                     "[[smoke]]\nname = \"half\"\ntype = \"box\"\nmin = [0.0, 0.0, 0.0]\n"
                                     "max = [4.0, 2.0, 2.0]\ndensity = 0.01\nvoxel = 0.05\n") +
            extra;
        return parseScene(text, "apart.toml", ".");
    };
    const CurveFitResult calib = readCalibrationJson("bocas");
    {
        const Scene scene = sceneWith("");
        const SurfaceSet surfaces(scene);
        const SaturationPredictor p(scene, surfaces, calib.curve, "cam");
        ASSERT_EQ(p.sights(), 2u);
        const SmokeField field = SmokeField::at(scene.volumes, 0.0);
        // The left line (to y = 0.75) runs inside the box (y ≥ 0) all the way; the right one (to
        // y = −0.75) only at its start, where y ≥ 0: none of it. Mean density: half the box's.
        EXPECT_NEAR(p.density(field), 0.5 * 0.01, 0.05 * 0.01);
        EXPECT_NEAR(p.saturation(field), calib.curve(p.density(field)), 1e-12);
    }
    {  // a wall in front of the right target: only the left is measured
        const Scene scene = sceneWith(
            "[[surfaces]]\nname = \"screen\"\nmaterial = \"paper\"\ntype = \"quad\"\n"
            "corner = [2.0, -1.0, 0.0]\nu = [0.0, 0.8, 0.0]\nv = [0.0, 0.0, 2.0]\n");
        const SurfaceSet surfaces(scene);
        const SaturationPredictor p(scene, surfaces, calib.curve, "cam");
        ASSERT_EQ(p.sights(), 1u);
        EXPECT_NEAR(p.density(SmokeField::at(scene.volumes, 0.0)), 0.01, 0.05 * 0.01);
    }
    {  // the camera turned away: neither lies in its image, refused
        const Scene scene = sceneWith("", "[-3.0, 0.0, 0.6]");
        const SurfaceSet surfaces(scene);
        EXPECT_THROW(SaturationPredictor(scene, surfaces, calib.curve, "cam"), Error);
    }
    {  // targets that are boxes (their centres inside them) are seen as well as quads
        const Scene scene = parseScene(
            "[scene]\nname = \"boxes\"\n[[materials]]\nname = \"paper\"\nalbedo = [0.8, 0.1, 0.1]\n"
            "[[surfaces]]\nname = \"target_left\"\nmaterial = \"paper\"\ntype = \"box\"\n"
            "position = [3.0, 0.75, 0.6]\nsize = [0.2, 0.3, 0.8]\n"
            "[[surfaces]]\nname = \"target_right\"\nmaterial = \"paper\"\ntype = \"box\"\n"
            "position = [3.0, -0.75, 0.6]\nsize = [0.2, 0.3, 0.8]\n"
            "[[cameras]]\nname = \"cam\"\nposition = [0.0, 0.0, 0.6]\nlook_at = [3.0, 0.0, 0.6]\n",
            "boxes.toml", ".");
        const SurfaceSet surfaces(scene);
        EXPECT_EQ(SaturationPredictor(scene, surfaces, calib.curve, "cam").sights(), 2u);
    }
    {  // a wall in front of both: refused, naming the scene
        const Scene scene = sceneWith(
            "[[surfaces]]\nname = \"screen\"\nmaterial = \"paper\"\ntype = \"quad\"\n"
            "corner = [2.0, -2.0, 0.0]\nu = [0.0, 4.0, 0.0]\nv = [0.0, 0.0, 2.0]\n");
        const SurfaceSet surfaces(scene);
        try {
            SaturationPredictor(scene, surfaces, calib.curve, "cam");
            FAIL() << "a camera that sees no target patch must be refused";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("apart.toml"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("none of the target"), std::string::npos) << e.what();
        }
    }
}
