// The saturation curve fit: recovery of known parameters within the reported errors over many
// seeds, inversion, degenerate sweeps; saturation measurement; the calibrate and saturation CLIs.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "smokescan/calib/calibration.hpp"
#include "smokescan/core/error.hpp"

#include "sanitized.hpp"
#include "scratch.hpp"

using namespace smokescan;
namespace fs = std::filesystem;

namespace {
// Synthetic data: the default sweep up to density 0.008 (12 densities; beyond it the curve falls
// to ~σ and noise could give impossible negative saturations), the curve S0 = 0.9, a = 1.3, b = 350
// (close to what the BOCAS calibration finds), Gaussian noise of σ = 0.004 on each saturation.
const SaturationCurve kTrue{0.9, 1.3, 350.0, 1 / 2.2};

std::vector<SaturationPoint> synthetic(uint64_t seed, double sigma = 0.004)
{
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> N(0, sigma);
    std::vector<SaturationPoint> pts;
    for (double rho : CalibrateConfig{}.densities)
        if (rho <= 0.008) pts.push_back({rho, kTrue(rho) + N(rng), sigma});
    return pts;
}

std::string calibrationErrorOf(const std::vector<SaturationPoint>& pts)
{
    try {
        fitSaturationCurve(pts);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(SaturationCurveFit, RecoversKnownParametersWithinReportedErrors)
{
    // Known σ, plain least squares: the z-scores (estimate − truth)/SE over 300 seeds must look
    // standard normal — that checks the estimates and the Ceres covariance together.
    CurveFitConfig cfg;
    cfg.loss = RobustLoss::None;
    cfg.scale_covariance_by_chi2 = false;
    const double truth[3] = {kTrue.S0, kTrue.a, kTrue.b};
    const int n = 300;
    for (int k = 0; k < 3; ++k) {
        double sum = 0, sum2 = 0;
        int within2 = 0;
        for (int s = 0; s < n; ++s) {
            const CurveFitResult f = fitSaturationCurve(synthetic(uint64_t(s)), cfg);
            ASSERT_TRUE(f.converged) << f.message;
            const double est[3] = {f.curve.S0, f.curve.a, f.curve.b};
            const double z = (est[k] - truth[k]) / f.std_error[size_t(k)];
            sum += z;
            sum2 += z * z;
            within2 += std::abs(z) < 2;
        }
        const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
        EXPECT_NEAR(mean, 0.0, 0.25) << "parameter " << k;
        EXPECT_NEAR(sd, 1.0, 0.2) << "parameter " << k;
        EXPECT_GE(within2, int(0.90 * n)) << "parameter " << k;
    }
}

TEST(SaturationCurveFit, RobustLossShrugsOffAnOutlier)
{
    auto pts = synthetic(7);
    pts[5].saturation += 0.1;  // one bad frame, 25 σ off
    const CurveFitResult robust = fitSaturationCurve(pts);
    CurveFitConfig plain;
    plain.loss = RobustLoss::None;
    const CurveFitResult ls = fitSaturationCurve(pts, plain);
    EXPECT_LT(std::abs(robust.curve.b - kTrue.b), std::abs(ls.curve.b - kTrue.b));
    EXPECT_NEAR(robust.curve.b, kTrue.b, 3 * robust.std_error[2]);
}

TEST(SaturationCurveFit, InversionRoundTripsWithPropagatedError)
{
    const CurveFitResult f = fitSaturationCurve(synthetic(3));
    for (double rho : {0.0005, 0.0028, 0.007, 0.011}) {
        const auto [r, se] = f.invert(f.curve(rho), 0.002);
        EXPECT_NEAR(r, rho, 1e-9 * std::max(1.0, rho));
        EXPECT_GT(se, 0.0);
    }
    // A larger saturation error gives a larger density error.
    EXPECT_GT(f.invert(0.14, 0.01).second, f.invert(0.14, 0.0).second);
    EXPECT_THROW(f.curve.invert(f.curve(0.0) + 0.01), Error);
    EXPECT_THROW(f.curve.invert(0.0), Error);
}

TEST(SaturationCurveFit, DegenerateSweepsAreRefused)
{
    EXPECT_NE(calibrationErrorOf({{0.001, 0.5, 0.01}, {0.001, 0.4, 0.01}, {0.001, 0.45, 0.01}, {0.001, 0.5, 0.01}})
                  .find("at least 4 distinct densities"),
              std::string::npos);
    std::vector<SaturationPoint> flat;
    for (double r : {0.0, 0.001, 0.002, 0.004, 0.008}) flat.push_back({r, 0.3, 0.01});
    EXPECT_NE(calibrationErrorOf(flat).find("does not change"), std::string::npos);
    auto nan = synthetic(1);
    nan[4].saturation = std::nan("");
    EXPECT_NE(calibrationErrorOf(nan).find("calibration point 5: is not finite"), std::string::npos);
    auto out = synthetic(1);
    out[2].saturation = 1.2;
    EXPECT_NE(calibrationErrorOf(out).find("outside [0, 1]"), std::string::npos);
}

TEST(Saturation, HsvAndMaskedStatistics)
{
    EXPECT_DOUBLE_EQ(hsvSaturation(1, 0, 0), 1.0);
    EXPECT_DOUBLE_EQ(hsvSaturation(0.5, 0.5, 0.5), 0.0);
    EXPECT_DOUBLE_EQ(hsvSaturation(0, 0, 0), 0.0);
    EXPECT_DOUBLE_EQ(hsvSaturation(200, 100, 50), 0.75);
    Image img(4, 2, 3);
    for (int x = 0; x < 4; ++x) {
        img.at(x, 0, 0) = 1.0f;  // row 0: saturation 1 − 128/255 (8-bit quantised)
        img.at(x, 0, 1) = img.at(x, 0, 2) = 128 / 255.0f;
        img.at(x, 1, 0) = img.at(x, 1, 1) = img.at(x, 1, 2) = 0.5f;  // row 1: grey
    }
    const auto s = maskedSaturation(img, [](int, int y) { return y == 0; });
    EXPECT_EQ(s.pixels, 4);
    EXPECT_NEAR(s.mean, 1 - 128 / 255.0, 1e-12);
    EXPECT_NEAR(s.stddev, 0.0, 1e-12);
    const auto all = maskedSaturation(img, [](int, int) { return true; });
    EXPECT_NEAR(all.mean, 0.5 * (1 - 128 / 255.0), 1e-12);
}

namespace {
struct Out {
    int status;
    std::string err;
};
Out run(const std::string& args)
{
    const fs::path e = smokescan::test::scratch("calib_err") / "stderr";
    const int rc = std::system((std::string(SMOKESCAN_CLI) + " " + args + " >/dev/null 2>" + e.string()).c_str());
    std::ifstream in(e);
    std::stringstream ss;
    ss << in.rdbuf();
    return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, ss.str()};
}
}  // namespace

TEST(SaturationCli, FramesFolderWithRectsAndFileNameTimes)
{
    const fs::path dir = smokescan::test::scratch("sat");
    fs::create_directories(dir / "frames");
    // Three frames whose 4×4 patch fades from saturated blue towards grey.
    for (int k = 0; k < 3; ++k) {
        Image img(10, 8, 3);
        for (float& v : img.data) v = 0.5f;
        for (int y = 2; y < 6; ++y)
            for (int x = 2; x < 6; ++x) {
                img.at(x, y, 0) = img.at(x, y, 1) = 0.2f + 0.2f * k;
                img.at(x, y, 2) = 0.8f;
            }
        writeImage((dir / "frames" / ("cam_" + std::to_string(10 * (k + 1)) + ".png")).string(), img);
    }
    const std::string csv = (dir / "sat.csv").string();
    const Out r = run("saturation " + (dir / "frames").string() + " --rect blue=2,2,4,4 --fps 10 --out " + csv);
    ASSERT_EQ(r.status, 0) << r.err;
    std::ifstream in(csv);
    std::string header, line;
    std::getline(in, header);
    EXPECT_EQ(header, "time_s,saturation,saturation_median,saturation_sd,pixels,blue,blue_median,blue_sd");
    double prev_s = 2;
    for (int k = 0; k < 3; ++k) {
        ASSERT_TRUE(std::getline(in, line));
        std::stringstream ss(line);
        double t, s;
        char c;
        ss >> t >> c >> s;
        EXPECT_DOUBLE_EQ(t, double(k + 1));
        const double want = hsvSaturation(204, std::lround((0.2 + 0.2 * k) * 255), std::lround((0.2 + 0.2 * k) * 255));
        EXPECT_NEAR(s, want, 1e-9);
        EXPECT_LT(s, prev_s);
        prev_s = s;
    }
    const Out bad =
        run("saturation " + (dir / "frames").string() + " --rect blue=2,2,4 --out " + (dir / "x.csv").string());
    EXPECT_NE(bad.status, 0);
    EXPECT_NE(bad.err.find("--rect: expects NAME=x,y,width,height"), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(dir / "x.csv"));
    fs::remove_all(dir);
}

TEST(CalibrateCli, WritesJsonAndPlotAndRefusesDegenerateSweeps)
{
    const fs::path dir = smokescan::test::scratch("cal");
    const std::string json = (dir / "c.json").string(), png = (dir / "c.png").string();
    const Out r =
        run("calibrate bocas --densities 0,0.0005,0.001,0.002,0.003,0.005,0.008,0.012 --spp 2 --width 96 --height 72 "
            "--out " +
            json + " --plot " + png);
    ASSERT_EQ(r.status, 0) << r.err;
    std::ifstream in(json);
    const auto j = nlohmann::json::parse(in);
    EXPECT_EQ(j["combined"]["points"].size(), 8u);
    EXPECT_GT(j["combined"]["parameters"]["floor"].get<double>(), 0.0);  // the camera's noise
    EXPECT_EQ(j["measured_patches"].size(), 3u);
    EXPECT_TRUE(j.contains("colour_mix"));
    EXPECT_GT(j["combined"]["parameters"]["b"].get<double>(), 0.0);
    EXPECT_EQ(j["combined"]["covariance"].size(), 3u);
    EXPECT_TRUE(j["patches"].contains("blue") && j["patches"].contains("yellow") && j["patches"].contains("gold"));
    // A reader needs only the file: the formula it states, with its parameters, reads the threshold
    // saturation at the threshold density it states.
    {
        const auto& q = j["combined"]["parameters"];
        const double S0 = q["S0"], a = q["a"], b = q["b"], g = q["gamma"], f = q["floor"];
        const double rho = j["threshold"]["density"];
        EXPECT_EQ(j["model"], "S(rho) = sqrt((1 - (1 - S0 / (1 + a*(exp(b*rho) - 1)))^gamma)^2 + floor^2)");
        const double S = std::sqrt(std::pow(1 - std::pow(1 - S0 / (1 + a * (std::exp(b * rho) - 1)), g), 2) + f * f);
        EXPECT_NEAR(S, j["threshold"]["saturation"].get<double>(), 1e-6);
    }
    EXPECT_TRUE(fs::exists(png));
    const std::string never = (dir / "never.json").string();
    const Out d = run("calibrate bocas --densities 0.001,0.002 --spp 1 --width 16 --height 12 --out " + never);
    EXPECT_NE(d.status, 0);
    EXPECT_NE(d.err.find("at least 4 distinct densities"), std::string::npos) << d.err;
    EXPECT_FALSE(fs::exists(never));
    fs::remove_all(dir);
}

TEST(SaturationCli, RenderedFramesWithIdMasks)
{
    // A rendered BOCAS frame and its id AOV: the patches are named by the scene's target surfaces.
    const fs::path dir = smokescan::test::scratch("satids");
    fs::create_directories(dir / "f");
    fs::create_directories(dir / "i");
    const Out r = run("render bocas --time 0 --spp 2 --width 64 --height 48 --out " +
                      (dir / "f" / "t_12.5.png").string() + " --ids " + (dir / "i" / "t_12.5.exr").string());
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string csv = (dir / "s.csv").string();
    const Out s =
        run("saturation " + (dir / "f").string() + " --ids " + (dir / "i").string() + " --scene bocas --out " + csv);
    ASSERT_EQ(s.status, 0) << s.err;
    std::ifstream in(csv);
    std::string header, line;
    std::getline(in, header);
    std::getline(in, line);
    EXPECT_NE(header.find(",blue,"), std::string::npos);
    EXPECT_NE(header.find(",yellow,"), std::string::npos);
    EXPECT_NE(header.find(",gold,"), std::string::npos);
    std::stringstream ss(line);
    double t, sat;
    char c;
    ss >> t >> c >> sat;
    EXPECT_DOUBLE_EQ(t, 12.5);
    EXPECT_GT(sat, 0.4);  // the clear-air target is strongly coloured
    const Out bad =
        run("saturation " + (dir / "f").string() + " --ids " + (dir / "i").string() + " --out " + csv + ".x");
    EXPECT_NE(bad.err.find("--ids: needs --scene"), std::string::npos) << bad.err;
    fs::remove_all(dir);
}

// The built-in calibration's converged points (calib/bocas.json, written by `calibrate bocas`):
// the colour-mixing curve with a drifting light describes every point within its errors; the
// one-light curve cannot (the drift is real: docs/calibration.md). Under that light the patches
// share one extinction, and it agrees with the one their colours give.
TEST(CalibrationBocas, TheDriftingLightCurveDescribesTheConvergedPointsWithOneExtinction)
{
    if (test::sanitized()) GTEST_SKIP() << "a long fit: the Release build";
    std::ifstream in(std::string(SMOKESCAN_SOURCE_DIR) + "/calib/bocas.json");
    ASSERT_TRUE(in.good());
    const auto j = nlohmann::json::parse(in);
    std::vector<PatchPoints> patches;
    for (const auto& [name, m] : j.at("measured_patches").items()) {
        PatchPoints pp;
        pp.name = name;
        pp.weight = m.at("weight").get<double>();
        pp.clear_colour = m.at("clear_colour").get<std::array<double, 3>>();
        pp.brightness = m.at("brightness_classes").get<std::vector<double>>();
        for (const auto& q : m.at("points")) {
            pp.points.push_back(
                {q.at("density").get<double>(), q.at("saturation").get<double>(), q.at("std_error").get<double>()});
            pp.floor.push_back(q.at("noise_floor").get<double>());
        }
        patches.push_back(pp);
    }
    ASSERT_EQ(patches.size(), 3u);
    const ColourMixFit drift = fitColourMix(patches, 1 / 2.2, true), one = fitColourMix(patches);
    ASSERT_TRUE(drift.converged) << drift.message;
    std::printf("chi2/dof: drifting light %.2f (%d dof), one light %.2f (%d dof)\n", drift.chi2 / drift.dof, drift.dof,
                one.chi2 / one.dof, one.dof);
    EXPECT_LT(drift.chi2 / drift.dof, 2.0);
    EXPECT_GT(one.chi2 / one.dof, 4.0);
    for (size_t p = 0; p < patches.size(); ++p)
        for (const auto& q : patches[p].points)
            EXPECT_LT(std::abs(drift.curve.patch(p, q.density) - q.saturation), 3.5 * q.sigma)
                << patches[p].name << " at " << q.density;
    // One extinction: each patch alone, under the light the joint fit measured, gives a b that the
    // others' agree with; under the one-colour light they cannot (blue's b runs 70 % above gold's).
    const PatchExtinctions under_drift = fitPatchesUnderLight(patches, 1 / 2.2, drift.curve);
    const PatchExtinctions under_one = fitPatchesUnderLight(patches, 1 / 2.2, one.curve);
    ASSERT_EQ(under_drift.dof, 2);
    ASSERT_EQ(under_one.dof, 2);
    for (const auto& [name, f] : under_drift.fits)
        std::printf("%s alone: b = %.1f +- %.1f under the drifting light, %.1f +- %.1f under one colour\n",
                    name.c_str(), f.curve.b, f.std_error[0], under_one.fits.at(name).curve.b,
                    under_one.fits.at(name).std_error[0]);
    EXPECT_GT(under_drift.p_value, 0.01) << "chi2 " << under_drift.chi2;
    EXPECT_LT(under_one.p_value, 1e-6) << "chi2 " << under_one.chi2;
    // And the extinction agrees, within 3 of their combined errors, with the one measured from the
    // patches' colours alone (light_mixing.hpp: no curve, no camera), which the one-colour fit's
    // does not.
    const double b_mix = j.at("light_mixing").at("b").get<double>();
    const double se_mix = j.at("light_mixing").at("b_std_error").get<double>();
    EXPECT_LT(std::abs(drift.curve.b - b_mix), 3 * std::hypot(drift.std_error[0], se_mix));
    EXPECT_GT(std::abs(one.curve.b - b_mix), 3 * std::hypot(one.std_error[0], se_mix));
}
