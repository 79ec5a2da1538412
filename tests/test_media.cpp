// Timelines, media, plumes and overlapping volumes against analytic answers.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <random>

#include "smokescan/core/error.hpp"
#include "smokescan/media/plume.hpp"
#include "smokescan/media/smoke.hpp"

using namespace smokescan;

TEST(Timeline, MachineMatchesOdeIntegration)
{
    const auto tl = DensityTimeline::machine({{20, 30}, {90, 130}}, 0.00022, 150.0);
    // Forward Euler with a tiny step on dρ/dt = q·on − ρ/τ.
    double rho = 0, t = 0;
    const double dt = 1e-3;
    for (int check = 0; check <= 360; check += 15) {
        for (; t < check - 1e-9; t += dt) {
            const bool on = (t >= 20 && t < 30) || (t >= 90 && t < 130);
            rho += dt * ((on ? 0.00022 : 0.0) - rho / 150.0);
        }
        EXPECT_NEAR(tl.at(check), rho, 2e-6 * 0.01 + 1e-3 * rho) << "t = " << check;
    }
    EXPECT_EQ(tl.at(10), 0.0);
}

TEST(Timeline, KeyframesInterpolateAndDecay)
{
    const auto lin = DensityTimeline::keyframes({{0, 0}, {10, 1}, {20, 1}}, DensityTimeline::Interp::Linear, 5.0);
    EXPECT_DOUBLE_EQ(lin.at(-1), 0);
    EXPECT_DOUBLE_EQ(lin.at(2.5), 0.25);
    EXPECT_DOUBLE_EQ(lin.at(15), 1);
    EXPECT_NEAR(lin.at(25), std::exp(-1.0), 1e-12);
    const auto ex = DensityTimeline::keyframes({{0, 1}, {10, 0.01}}, DensityTimeline::Interp::Exp);
    EXPECT_NEAR(ex.at(5), 0.1, 1e-12);
    const auto st = DensityTimeline::keyframes({{0, 1}, {10, 3}}, DensityTimeline::Interp::Step);
    EXPECT_DOUBLE_EQ(st.at(9.9), 1);
    EXPECT_THROW(DensityTimeline::keyframes({{0, 1}, {0, 2}}, DensityTimeline::Interp::Linear), Error);
    EXPECT_THROW(DensityTimeline::keyframes({{0, -1}}, DensityTimeline::Interp::Linear), Error);
    EXPECT_THROW(DensityTimeline::machine({{5, 2}}, 1, 1), Error);
    EXPECT_THROW(DensityTimeline::machine({{0, 5}, {4, 6}}, 1, 1), Error);
}

TEST(Medium, AngstromLaw)
{
    const Medium soot = Medium::preset("soot");  // Å = 1
    EXPECT_NEAR(soot.sigmaT(905) / soot.sigmaT(550), 550.0 / 905.0, 1e-12);
    EXPECT_NEAR(soot.sigmaT(700) / soot.sigmaT(550), 550.0 / 700.0, 1e-12);
    const Medium fine = Medium::preset("fine_smoke");  // Å = 2
    EXPECT_NEAR(fine.sigmaT(905) / fine.sigmaT(550), std::pow(550.0 / 905.0, 2), 1e-12);
    EXPECT_NEAR(Medium::preset("theatrical_fog").sigmaT(785), Medium::kCalibratedSigmaT, 1e-12);
    EXPECT_THROW(Medium::preset("steam"), Error);
}

namespace {
SmokeVolume boxVolume(const std::string& name, Vec3 lo, Vec3 hi, double rho, SmokeRole role = SmokeRole::Regional)
{
    SmokeVolume v;
    v.name = name;
    v.role = role;
    v.source = std::make_shared<const DensityGrid>(DensityGrid::box(lo, hi, rho, 0.05));
    return v;
}
}  // namespace

TEST(SmokeField, OverlappingVolumesAddExactly)
{
    // Box faces on the 0.05 m voxel faces (±0.025 offsets), so the voxelised boxes are exact.
    std::vector<SmokeVolume> vols = {boxVolume("a", {-0.025, -1.025, -1.025}, {2.025, 1.025, 1.025}, 0.002),
                                     boxVolume("b", {0.975, -0.525, -0.525}, {3.025, 0.525, 0.525}, 0.003)};
    vols[1].medium = Medium::preset("soot");
    vols[1].timeline = DensityTimeline::constant(2.0);
    const SmokeField f = SmokeField::at(vols, 0.0);
    const Ray r{Vec3(-1, 0.1, 0.2), Vec3::UnitX()};
    BeamQuery q;
    q.wavelength_nm = 905;
    q.want_profile = true;
    const BeamSmoke s = f.trace(r, 0.0, 10.0, q);
    const double col_a = 0.002 * 2.05, col_b = 2 * 0.003 * 2.05;
    EXPECT_NEAR(s.column_regional, col_a + col_b, 1e-9);
    const double tau = Medium::kCalibratedSigmaT * col_a + Medium::preset("soot").sigmaT(905) * col_b;
    EXPECT_NEAR(s.tau, tau, 1e-6 * tau);
    // Beer–Lambert: the profile integrates to the same optical depth, and the overlap adds.
    double from_profile = 0;
    for (const auto& p : s.sigma_t_profile) from_profile += p.density * (p.t1_m - p.t0_m);
    EXPECT_NEAR(from_profile, tau, 1e-6 * tau);
    ASSERT_EQ(s.sigma_t_profile.size(), 3u);
    EXPECT_NEAR(s.sigma_t_profile[1].t0_m, 1.975, 1e-9);
    EXPECT_NEAR(s.sigma_t_profile[1].density,
                Medium::kCalibratedSigmaT * 0.002 + Medium::preset("soot").sigmaT(905) * 0.006, 1e-6);
}

TEST(SmokeField, ABeamMeetsEveryGridItsSegmentCrosses)
{
    // The field skips a grid whose bounds a beam misses: each beam's column must still be the sum
    // of every grid's own integral over the same segment, box-filtered and trilinear (which reaches
    // half a voxel beyond the outer voxels' faces). Beams from inside and outside the boxes, along
    // the axes both ways (a zero direction component) and at random, segments that stop short of
    // a box or start past it, and beams parallel to a face just outside it.
    std::vector<SmokeVolume> vols = {boxVolume("a", {-0.025, -1.025, -1.025}, {2.025, 1.025, 1.025}, 0.002),
                                     boxVolume("b", {2.975, 1.975, -0.525}, {4.025, 3.025, 0.525}, 0.003),
                                     boxVolume("c", {-3.025, -0.525, 1.975}, {-1.975, 0.525, 3.025}, 0.004)};
    const SmokeField f = SmokeField::at(vols, 0.0);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> U(-4, 4), T(0, 6);
    int crossing = 0, grazing = 0;
    auto check = [&](const Ray& r, double t0, double t1, int n) {
        for (Reconstruction recon : {Reconstruction::Box, Reconstruction::Trilinear}) {
            double want = 0;
            for (const SmokeVolume& v : vols) want += v.gridAt(0.0)->integrate(r, t0, t1, recon);
            BeamQuery q;
            q.recon = recon;
            q.want_profile = true;
            const BeamSmoke s = f.trace(r, t0, t1, q);
            EXPECT_NEAR(s.column_regional, want, 1e-12) << "beam " << n;
            double from_profile = 0;  // the profile (a lone grid's swapped in) holds the same smoke
            for (const auto& g : s.sigma_t_profile) from_profile += g.density * (g.t1_m - g.t0_m);
            EXPECT_NEAR(from_profile, s.tau, 1e-9 * std::max(1.0, s.tau)) << "beam " << n;
            crossing += recon == Reconstruction::Box && want > 0;
        }
    };
    for (int n = 0; n < 3000; ++n) {
        Vec3 d =
            n % 3 == 0 ? Vec3::Unit(n % 9 / 3) * (n % 4 == 0 ? 1.0 : -1.0) : Vec3(U(rng), U(rng), U(rng)).normalized();
        if (n % 7 == 0) d = Vec3(d.x(), d.y(), 0).normalized();  // in a horizontal plane
        const Vec3 o(U(rng), U(rng), U(rng));
        if (n % 2 == 1) {  // half of the beams aimed near a box's centre
            static const Vec3 centres[3] = {{1, 0, 0}, {3.5, 2.5, 0}, {-2.5, 0, 2.5}};
            d = (centres[n % 3] + 0.3 * Vec3(U(rng), U(rng), U(rng)) - o).normalized();
        }
        double t0 = T(rng), t1 = T(rng);
        if (t1 < t0) std::swap(t0, t1);
        check(Ray{o, d}, t0, t1, n);
    }
    EXPECT_GT(crossing, 400);  // the test must see smoke often
    // Along box a's faces, a quarter voxel outside: only the trilinear reconstruction has smoke there.
    for (int side = 0; side < 6; ++side) {
        const int axis = side / 2;
        const double out = side % 2 ? 1.025 + 0.0125 : -1.025 - 0.0125;
        Vec3 o(1.0, 0.1, 0.2), d = Vec3::UnitX();
        if (axis == 0) {  // beyond the x faces: run along y
            o = Vec3(side % 2 ? 2.025 + 0.0125 : -0.025 - 0.0125, -3, 0.2);
            d = Vec3::UnitY();
        } else {
            o[axis] = out;
            o.x() = -2;
        }
        check(Ray{o, d}, 0.0, 6.0, 10000 + side);
        grazing += vols[0].gridAt(0.0)->integrate(Ray{o, d}, 0.0, 6.0, Reconstruction::Trilinear) > 0;
    }
    EXPECT_EQ(grazing, 6);
}

TEST(Plume, DeterministicAndMassConserving)
{
    PlumeConfig c;
    c.source_m = Vec3(1, 2, 0);
    c.wind_m_s = Vec3(0.3, 0, 0);
    c.seed = 42;
    const auto b1 = plumeBlobs(c, 12.0);
    plumeBlobs(c, 3.0);  // other times simulated first change nothing
    const auto b2 = plumeBlobs(c, 12.0);
    ASSERT_EQ(b1.size(), b2.size());
    ASSERT_EQ(b1.size(), size_t(12.0 * c.rate_per_s) + 1);
    for (size_t i = 0; i < b1.size(); ++i) EXPECT_EQ(b1[i].centre_m, b2[i].centre_m);
    // Mass of each puff (before its fade) is constant: peak·σ³ = peak0·r0³.
    for (const auto& b : b1)
        EXPECT_NEAR(b.peak * std::pow(b.sigma_m, 3), c.peak_density * std::pow(c.radius_m, 3), 1e-12);
    // The grid holds that mass: Σ voxels·h³ ≈ Σ peak·(2π)^{3/2}σ³ · P(χ²₃ ≤ 9) (3σ cut-off).
    const DensityGrid g = rasterisePlume(c, 12.0);
    const double h = c.voxel_m, p3 = 0.97070911346;  // P(|x| ≤ 3σ) for a 3-D Gaussian
    double mass_grid = 0, mass_blobs = 0;
    for (const auto& b : b1) mass_blobs += b.peak * std::pow(2 * M_PI, 1.5) * std::pow(b.sigma_m, 3) * p3;
    // Integrate the grid along many parallel rays through it (a box-filtered volume integral).
    const Aabb bb = g.worldBounds();
    for (double y = bb.lo.y() + h / 2; y < bb.hi.y(); y += h)
        for (double z = bb.lo.z() + h / 2; z < bb.hi.z(); z += h)
            mass_grid += g.integrate(Ray{Vec3(bb.lo.x() - 1, y, z), Vec3::UnitX()}, 0, 100) * h * h;
    EXPECT_NEAR(mass_grid, mass_blobs, 0.02 * mass_blobs);
    // A different seed gives a different plume.
    c.seed = 43;
    EXPECT_NE(plumeBlobs(c, 12.0)[3].centre_m, b1[3].centre_m);
}

TEST(Plume, EachVoxelSumsItsPuffsWhateverTheThreadCount)
{
    // The puffs rasterised in slabs on every thread, and on one: each voxel holds the sum of its
    // puffs' Gaussians (within 3σ), as a voxel-by-voxel sum of them gives it.
    PlumeConfig c;
    c.source_m = Vec3(0.3, -0.2, 0.1);
    c.wind_m_s = Vec3(0.4, 0.1, 0.05);
    c.spread_m_s = 0.1;
    c.seed = 7;
    const double t = 9.0, h = c.voxel_m;
    const DensityGrid many = rasterisePlume(c, t);
    const DensityGrid one = [&] {
        tbb::global_control only(tbb::global_control::max_allowed_parallelism, 1);
        return rasterisePlume(c, t);
    }();
    EXPECT_EQ(many.info().active_voxels, one.info().active_voxels);
    EXPECT_GT(many.info().leaf_nodes, 8);  // several slabs
    const std::vector<DensityGrid::Blob> blobs = plumeBlobs(c, t);
    const Aabb bb = many.worldBounds();
    int checked = 0, inside = 0;
    for (double x = bb.lo.x() + h / 2; x < bb.hi.x(); x += 3 * h)
        for (double y = bb.lo.y() + h / 2; y < bb.hi.y(); y += 2 * h)
            for (double z = bb.lo.z() + h / 2; z < bb.hi.z(); z += 2 * h) {
                // The voxel whose centre is nearest (x, y, z), its value by a ray across it alone.
                const Vec3 centre = (Vec3(x, y, z) / h).array().round().matrix() * h;
                const Ray across{centre - Vec3(h / 2, 0, 0), Vec3::UnitX()};
                const double got = many.integrate(across, 0, h) / h;
                EXPECT_EQ(got, one.integrate(across, 0, h) / h);
                double want = 0;
                for (const auto& b : blobs) {
                    const double d2 = ((centre - b.centre_m) / h).squaredNorm(), r = 3 * b.sigma_m / h;
                    if (d2 <= r * r) want += b.peak * std::exp(-d2 * h * h / (2 * b.sigma_m * b.sigma_m));
                }
                EXPECT_NEAR(got, want, 1e-6 * c.peak_density + 1e-6 * want) << centre.transpose();
                ++checked;
                inside += want > 0;
            }
    EXPECT_GT(inside, 200);
    EXPECT_GT(checked, inside);
}
