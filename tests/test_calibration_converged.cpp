// The converged saturation measurement (camera/target_radiance.hpp, measureConvergedSaturation):
// what the calibration reads must not depend on the number of samples. At densities around the
// threshold, the default measurement and one with 16 times the samples (another seed) must agree
// within their stated errors, and so must the density at which they read S = 0.14. The former
// measurement (per-pixel saturation of a 4-spp frame) fails the same comparison.
#include <gtest/gtest.h>

#include <cmath>

#include "plant.hpp"
#include "smokescan/calib/calibration.hpp"
#include "smokescan/camera/saturation_render.hpp"
#include "smokescan/scene/scene_io.hpp"

using namespace smokescan;

namespace {

struct Reading {
    double s = 0, se = 0;
};

Reading converged(const Scene& s, const SurfaceSet& set, const TargetRadianceConfig& f, uint64_t seed)
{
    RenderConfig rc;
    rc.width = 160;
    rc.height = 120;
    rc.seed = seed;
    rc.progress = false;
    const TargetSaturation t = measureConvergedSaturation(s, set, rc, "target_", f);
    return {t.all.mean, t.se};
}

}  // namespace

TEST(CalibrationConverged, SixteenTimesTheSamplesReadTheSameSaturation)
{
    if (test::sanitized()) GTEST_SKIP() << "16× the samples of two frames: the Release build";
    const Scene bocas = loadScene("bocas");
    const std::vector<double> rho = {0.0024, 0.0032};  // either side of S = 0.14 (at 0.0028)
    TargetRadianceConfig def, more;
    def.max_batches = def.min_batches;  // exactly 16× below (the default may add batches)
    more.batch_spp = 16 * def.batch_spp;
    more.min_batches = more.max_batches = def.min_batches;
    std::vector<Reading> a, b;
    for (double r : rho) {
        const Scene s = uniformSmokeScene(bocas, r);
        const SurfaceSet set(s);
        a.push_back(converged(s, set, def, 3));
        b.push_back(converged(s, set, more, 4));
        std::printf("rho %.4f: default %.4f ± %.4f, 16x %.4f ± %.4f\n", r, a.back().s, a.back().se, b.back().s,
                    b.back().se);
        EXPECT_NEAR(a.back().s, b.back().s, 3 * std::hypot(a.back().se, b.back().se)) << r;
        EXPECT_LT(a.back().se, 0.006);  // the default at 32 spp: a useful measurement (3 dof in its error)
    }
    // The density at S = 0.14, by interpolation in ln S between the two, with its error.
    auto at = [&](const std::vector<Reading>& v, double& se) {
        const double l0 = std::log(v[0].s), l1 = std::log(v[1].s), x = (std::log(0.14) - l0) / (l1 - l0);
        const double d0 = v[0].se / v[0].s, d1 = v[1].se / v[1].s;  // errors of ln S
        const double dx0 = (x - 1) / (l1 - l0), dx1 = -x / (l1 - l0);
        se = (rho[1] - rho[0]) * std::hypot(dx0 * d0, dx1 * d1);
        return rho[0] + x * (rho[1] - rho[0]);
    };
    double se_a = 0, se_b = 0;
    const double ra = at(a, se_a), rb = at(b, se_b);
    std::printf("density at S = 0.14: default %.5f ± %.5f, 16x %.5f ± %.5f\n", ra, se_a, rb, se_b);
    EXPECT_NEAR(ra, rb, 3 * std::hypot(se_a, se_b));

    // The check has power: per-pixel saturation of a 4-spp frame reads far more saturated.
    const Scene s = uniformSmokeScene(bocas, rho[0]);
    const SurfaceSet set(s);
    RenderConfig rc;
    rc.width = 160;
    rc.height = 120;
    rc.spp = 4;
    rc.progress = false;
    const TargetSaturation old = measureTargetSaturation(s, set, rc, "target_");
    std::printf("4-spp per-pixel: %.4f\n", old.all.mean);
    EXPECT_GT(old.all.mean - b[0].s, 10 * b[0].se);
}
