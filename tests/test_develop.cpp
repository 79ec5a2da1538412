// The camera model (camera/develop.hpp) against its closed forms: a noiseless camera is the sRGB
// curve of the exposed radiance, exactly; a flat grey patch through a noisy one reads the HSV
// saturation that its noise predicts.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "smokescan/camera/develop.hpp"
#include "smokescan/camera/saturation.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/render/renderer.hpp"
#include "smokescan/scene/scene_io.hpp"

using namespace smokescan;

namespace {

/// d sRGB / d linear at v (v above the linear toe).
double srgbSlope(double v) { return 1.055 / 2.4 * std::pow(v, 1 / 2.4 - 1); }

Image flatImage(int n, double r, double g, double b)
{
    Image im(n, n, 3);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            im.at(x, y, 0) = float(r);
            im.at(x, y, 1) = float(g);
            im.at(x, y, 2) = float(b);
        }
    return im;
}

struct Stats {
    double mean_s = 0, sd_channel = 0, mean_channel = 0;
};

Stats measure(const Image& frame)
{
    Stats st;
    const double n = double(frame.width) * frame.height;
    double sum = 0, sum2 = 0;
    for (int y = 0; y < frame.height; ++y)
        for (int x = 0; x < frame.width; ++x) {
            st.mean_s += hsvSaturation(frame.at(x, y, 0), frame.at(x, y, 1), frame.at(x, y, 2)) / n;
            sum += frame.at(x, y, 1);
            sum2 += double(frame.at(x, y, 1)) * frame.at(x, y, 1);
        }
    st.mean_channel = sum / n;
    st.sd_channel = std::sqrt(sum2 / n - st.mean_channel * st.mean_channel);
    return st;
}

}  // namespace

TEST(Develop, NoiselessCameraIsTheSrgbCurveOfTheExposedRadiance)
{
    CameraSensor s;
    s.noise = false;
    s.bits = 0;
    Image rad(3, 1, 3);
    const float v[3][3] = {{0.02f, 0.3f, 0.7f}, {0.5f, 0.4f, 0.1f}, {2.0f, 0.001f, 0.3f}};
    for (int x = 0; x < 3; ++x)
        for (int c = 0; c < 3; ++c) rad.at(x, 0, c) = v[x][c];
    const double k = 0.9;
    const Image out = develop(rad, s, k, 1);
    for (int x = 0; x < 3; ++x) {
        for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(out.at(x, 0, c), float(srgbEncode(std::min(1.0, k * v[x][c]))));
        EXPECT_FLOAT_EQ(float(hsvSaturation(out.at(x, 0, 0), out.at(x, 0, 1), out.at(x, 0, 2))),
                        float(hsvSaturation(srgbEncode(k * v[x][0]), srgbEncode(k * v[x][1]),
                                            srgbEncode(std::min(1.0, k * v[x][2])))));
    }
    // 8-bit output is that value rounded to a multiple of 1/255.
    s.bits = 8;
    const Image q = develop(rad, s, k, 1);
    EXPECT_FLOAT_EQ(q.at(1, 0, 0), float(std::round(255 * srgbEncode(k * 0.5)) / 255));
}

TEST(Develop, FlatGreyPatchReadsTheSaturationItsNoisePredicts)
{
    // Three channels of a grey pixel are independent normals of sd σ_y (encoded) around y. Their
    // range has mean 3σ_y/√π, so the HSV saturation (max − min)/max has mean 3σ_y/(√π·y) to first
    // order in σ_y/y (kept below 0.2 % here, so the first order is exact to the test's tolerance),
    // with σ_y = sRGB′(v)·√(v·full_well + read_noise²)/full_well at the exposed signal v.
    const double v = 0.5;
    for (const auto& [full_well, read_noise] : {std::pair{1e6, 0.0}, std::pair{1e6, 1500.0}, std::pair{4e5, 300.0}}) {
        CameraSensor s;
        s.full_well_e = full_well;
        s.read_noise_e = read_noise;
        s.bits = 0;
        const Stats st = measure(develop(flatImage(300, v, v, v), s, 1.0, 7));
        const double sigma_y = srgbSlope(v) * std::sqrt(v * full_well + read_noise * read_noise) / full_well;
        const double y = srgbEncode(v);
        EXPECT_NEAR(st.mean_channel, y, 4 * sigma_y / 300);
        EXPECT_NEAR(st.sd_channel / sigma_y, 1.0, 0.02) << full_well << " e-, read noise " << read_noise;
        EXPECT_NEAR(st.mean_s / (3 * sigma_y / (std::sqrt(M_PI) * y)), 1.0, 0.02) << full_well << " e-";
    }
}

TEST(Develop, EightBitNoiseAddsTheQuantisationVariance)
{
    // The default webcam at mid-grey: σ_y ≈ 1.5 LSB, so rounding adds LSB²/12 to a channel's
    // variance (Sheppard) but leaves the mean range of three channels as without it. A grey
    // patch's saturation (max − min)/max of three channels y + σ·Z_i is, to second order in σ/y,
    // (σ/y)·(E[R] − (σ/y)·E[R·M]) with R the range and M the maximum of three standard normals:
    // E[R] = 3/√π = 1.6926 and E[R·M] = E[M²] − E[M·m] = (1 + √3/2π) + √3/π = 1.8270 (the order
    // statistics' product moments: E[X(1)X(2)] = √3/2π, and all of them sum to 0). The first-order
    // form greyNoiseSaturation uses is 1.4 % high here; counting LSB²/12 in σ would be 3 % high.
    // The mean over 600² pixels is known to about 0.00002.
    CameraSensor s;
    const double v = 0.18, lsb = 1.0 / 255;
    const Stats st = measure(develop(flatImage(600, v, v, v), s, 1.0, 3));
    const double sigma_y =
        srgbSlope(v) * std::sqrt(v * s.full_well_e + s.read_noise_e * s.read_noise_e) / s.full_well_e;
    EXPECT_NEAR(st.sd_channel / std::sqrt(sigma_y * sigma_y + lsb * lsb / 12), 1.0, 0.05);
    const double u = sigma_y / srgbEncode(v);
    const double ER = 3 / std::sqrt(M_PI), ERM = 1 + std::sqrt(3.0) / (2 * M_PI) + std::sqrt(3.0) / M_PI;
    const double second = u * (ER - u * ERM);
    const double with_lsb = 3 * std::sqrt(sigma_y * sigma_y + lsb * lsb / 12) / (std::sqrt(M_PI) * srgbEncode(v));
    std::printf("mean saturation %.5f: second order %.5f, first order %.5f, with the rounding's variance %.5f\n",
                st.mean_s, second, u * ER, with_lsb);
    EXPECT_NEAR(st.mean_s, second, 0.0001);
    EXPECT_GT(std::abs(st.mean_s - with_lsb), 0.0005);  // the rounding's variance is not in the mean
    EXPECT_NEAR(greyNoiseSaturation(s, v), u * ER, 1e-12);
}

TEST(Develop, FewPhotonsArePoissonAndTheFullWellClips)
{
    CameraSensor s;
    s.full_well_e = 1000;
    s.read_noise_e = 0;
    s.bits = 0;
    // 5 electrons on average: the decoded signal's mean and variance are Poisson's (5 and 5).
    const Image dark = develop(flatImage(300, 0.005, 0.005, 0.005), s, 1.0, 11);
    double m = 0, m2 = 0;
    const double n = 300.0 * 300.0;
    for (int y = 0; y < 300; ++y)
        for (int x = 0; x < 300; ++x) {
            const double e = dark.at(x, y, 0), lin = e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
            m += lin * 1000 / n;
            m2 += lin * 1000 * lin * 1000 / n;
        }
    EXPECT_NEAR(m, 5.0, 4 * std::sqrt(5.0 / n));
    EXPECT_NEAR(m2 - m * m, 5.0, 0.1);
    // Poisson, not a normal of the same mean and variance: no electron in e^−5 of the pixels.
    double zero = 0;
    for (int y = 0; y < 300; ++y)
        for (int x = 0; x < 300; ++x) zero += dark.at(x, y, 0) == 0.0f;
    const double p0 = std::exp(-5.0);
    EXPECT_NEAR(zero / n, p0, 4 * std::sqrt(p0 * (1 - p0) / n));
    // Twice the full well reads 1, whatever the noise.
    const Image bright = develop(flatImage(4, 2.0, 2.0, 2.0), s, 1.0, 11);
    EXPECT_FLOAT_EQ(bright.at(0, 0, 1), 1.0f);
}

TEST(Develop, SceneCamerasReadTheirSensorTable)
{
    const Scene sc = parseScene(R"(
[[cameras]]
name = "cam"
sensor = { full_well_e = 5000.0, read_noise_e = 4.0, bits = 10, white_balance = [1.1, 1.0, 0.9], noise = false }
)",
                                "cam.toml", ".");
    const CameraSensor& s = sc.cameras[0].sensor;
    EXPECT_EQ(s.full_well_e, 5000.0);
    EXPECT_EQ(s.read_noise_e, 4.0);
    EXPECT_EQ(s.bits, 10);
    EXPECT_EQ(s.white_balance[0], 1.1);
    EXPECT_FALSE(s.noise);
    for (const char* bad : {"sensor = { bits = 17 }", "sensor = { full_well_e = 1.0 }", "sensor = { noise = 1 }",
                            "sensor = { white_balance = [0.0, 1.0, 1.0] }", "sensor = { iso = 100 }"}) {
        EXPECT_THROW(parseScene(std::string("[[cameras]]\nname = \"c\"\n") + bad + "\n", "c.toml", "."), Error) << bad;
    }
}
