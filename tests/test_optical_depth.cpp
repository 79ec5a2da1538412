// Optical depth through VDB grids against analytic answers and an independent reference.
//
// Test grids are built here with OpenVDB directly; the reference integrator enumerates every voxel
// face crossing of the ray, sorts them and sums value × length at the midpoints — a naive
// algorithm sharing no code with the hierarchical walker.
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include <algorithm>
#include <random>

#include "../src/media/vdb_grid.hpp"

using namespace smokescan;

namespace {

openvdb::FloatGrid::Ptr makeGrid(double voxel, const openvdb::Vec3d& offset)
{
    ensureOpenVdb();
    auto g = openvdb::FloatGrid::create(0.0f);
    auto xf = openvdb::math::Transform::createLinearTransform(voxel);
    xf->postTranslate(offset);
    g->setTransform(xf);
    return g;
}

/// World box covered by index voxels [lo, hi] (box filtering: faces at ±½).
Aabb worldBox(const openvdb::FloatGrid& g, const openvdb::Coord& lo, const openvdb::Coord& hi)
{
    Aabb b;
    const auto a = g.transform().indexToWorld(lo.asVec3d() - 0.5);
    const auto c = g.transform().indexToWorld(hi.asVec3d() + 0.5);
    b.extend(Vec3(a[0], a[1], a[2]));
    b.extend(Vec3(c[0], c[1], c[2]));
    return b;
}

double chord(const Aabb& b, const Ray& r, double t0, double t1) { return b.clip(r, t0, t1) ? t1 - t0 : 0.0; }

struct RefPiece {
    double ta, tb, v;
};

/// The ray's pieces of constant value on [t0, t1], in order.
std::vector<RefPiece> referencePieces(const openvdb::FloatGrid& g, const Ray& r, double t0, double t1)
{
    const auto& xf = g.transform();
    auto toIdx = [&](double t) {
        const Vec3 p = r.at(t);
        return xf.worldToIndex(openvdb::Vec3d(p.x(), p.y(), p.z()));
    };
    const openvdb::Vec3d a = toIdx(t0), b = toIdx(t1);
    std::vector<double> ts = {t0, t1};
    for (int ax = 0; ax < 3; ++ax) {
        const double x0 = a[ax] + 0.5, x1 = b[ax] + 0.5;  // faces at integers in cell space
        if (x0 == x1) continue;
        for (double k = std::ceil(std::min(x0, x1)); k <= std::floor(std::max(x0, x1)); k += 1.0)
            ts.push_back(t0 + (t1 - t0) * (k - x0) / (x1 - x0));
    }
    std::sort(ts.begin(), ts.end());
    auto acc = g.getConstAccessor();
    std::vector<RefPiece> out;
    for (size_t i = 0; i + 1 < ts.size(); ++i) {
        const double h = ts[i + 1] - ts[i];
        if (h <= 0) continue;
        const openvdb::Vec3d m = toIdx(0.5 * (ts[i] + ts[i + 1]));
        const openvdb::Coord c(int(std::floor(m[0] + 0.5)), int(std::floor(m[1] + 0.5)), int(std::floor(m[2] + 0.5)));
        out.push_back({ts[i], ts[i + 1], double(acc.getValue(c))});
    }
    return out;
}

double reference(const openvdb::FloatGrid& g, const Ray& r, double t0, double t1)
{
    double sum = 0;
    for (const RefPiece& p : referencePieces(g, r, t0, t1)) sum += p.v * (p.tb - p.ta);
    return sum;
}

Ray ray(const Vec3& o, const Vec3& d) { return Ray{o, d.normalized()}; }

void expectRel(double got, double want, const char* what)
{
    EXPECT_NEAR(got, want, 1e-6 * std::abs(want) + 1e-12) << what;  // relative (absolute only at 0)
}

struct BoxCase {
    const char* name;
    Ray r;
    double t0, t1;
};

/// Rays against a box whose voxels have edge h.
std::vector<BoxCase> boxRays(const Aabb& b, double h)
{
    const Vec3 c = 0.5 * (b.lo + b.hi), e = b.hi - b.lo;
    return {
        {"axis +x", ray(Vec3(b.lo.x() - 1, c.y(), c.z()), Vec3::UnitX()), 0, 100},
        {"axis -z", ray(Vec3(c.x() + 0.1 * e.x(), c.y(), b.hi.z() + 2), -Vec3::UnitZ()), 0, 100},
        {"diagonal", ray(b.lo - Vec3::Constant(0.7), Vec3(1, 1, 1)), 0, 100},
        {"diagonal negative", ray(b.hi + Vec3(0.3, 0.5, 0.9), Vec3(-1, -0.8, -0.6)), 0, 100},
        {"oblique", ray(Vec3(b.lo.x() - 0.3, b.lo.y() + 0.2 * e.y(), c.z()), Vec3(1, 0.31, -0.17)), 0, 100},
        {"starts inside", ray(c + 0.1 * e, Vec3(-0.3, 1, 0.2)), 0, 100},
        {"inside, short", ray(c, Vec3(0.2, -0.1, 1)), 0.01, 0.2 * e.z()},
        {"grazing face", ray(Vec3(b.lo.x() - 1, b.lo.y() + 1e-7 * e.y(), c.z()), Vec3::UnitX()), 0, 100},
        {"grazing corner", ray(Vec3(b.lo.x() - 1, b.hi.y() - 0.01 * e.y(), c.z()), Vec3(1, 0.02, 0)), 0, 100},
        // Lies in interior voxel-face planes (z and y): both neighbours hold the same value.
        {"in a voxel face plane", ray(Vec3(b.lo.x() - 1, b.lo.y() + 3 * h, b.lo.z() + 2 * h), Vec3::UnitX()), 0, 100},
        {"miss", ray(Vec3(b.lo.x() - 1, b.hi.y() + 0.1, c.z()), Vec3::UnitX()), 0, 100},
    };
}

}  // namespace

TEST(OpticalDepth, HomogeneousBoxOfVoxels)
{
    auto g = makeGrid(0.1, {0.3, -1.2, 0.05});
    const openvdb::Coord lo(-5, 3, -20), hi(34, 41, 12);
    g->tree().fill(openvdb::CoordBBox(lo, hi), 0.8f, true);
    g->tree().voxelizeActiveTiles();
    ASSERT_EQ(g->tree().activeTileCount(), 0u);
    const DensityGrid dg = wrapFloatGrid(g);
    const Aabb b = worldBox(*g, lo, hi);
    for (const auto& c : boxRays(b, 0.1)) {
        const double want = 0.8 * chord(b, c.r, c.t0, c.t1);
        expectRel(dg.integrate(c.r, c.t0, c.t1), want, c.name);
        expectRel(reference(*g, c.r, c.t0, c.t1), want, c.name);
    }
}

TEST(OpticalDepth, HomogeneousBoxOfTiles)
{
    auto g = makeGrid(0.25, {-3.0, 2.0, 1.0});
    // [0,255]³ becomes 128³ tiles of the upper internal nodes; [8,135]×… adds 8³ tiles.
    const openvdb::Coord lo(-128, 0, 0), hi(127, 255, 255);
    g->tree().fill(openvdb::CoordBBox(lo, hi), 0.002f, true);
    ASSERT_GT(g->tree().activeTileCount(), 0u);
    ASSERT_EQ(g->tree().leafCount(), 0u);
    const DensityGrid dg = wrapFloatGrid(g);
    const Aabb b = worldBox(*g, lo, hi);
    for (const auto& c : boxRays(b, 0.25))
        expectRel(dg.integrate(c.r, c.t0, c.t1), 0.002 * chord(b, c.r, c.t0, c.t1), c.name);

    auto g2 = makeGrid(0.25, {0, 0, 0});
    const openvdb::Coord lo2(8, -16, 24), hi2(135, 7, 71);  // 8-aligned: lower-node tiles
    g2->tree().fill(openvdb::CoordBBox(lo2, hi2), 1.5f, true);
    ASSERT_GT(g2->tree().activeTileCount(), 0u);
    const DensityGrid dg2 = wrapFloatGrid(g2);
    const Aabb b2 = worldBox(*g2, lo2, hi2);
    for (const auto& c : boxRays(b2, 0.25))
        expectRel(dg2.integrate(c.r, c.t0, c.t1), 1.5 * chord(b2, c.r, c.t0, c.t1), c.name);
}

TEST(OpticalDepth, BoxFromMeshMatchesItsBounds)
{
    // Box faces on voxel faces, so voxel-centre inclusion reproduces the box exactly.
    const double h = 0.05;
    const Vec3 lo(-0.975, -0.475, 0.025), hi(1.525, 0.975, 0.775);
    const DensityGrid dg = DensityGrid::box(lo, hi, 0.0028, h);
    Aabb b;
    b.extend(lo);
    b.extend(hi);
    expectRel(dg.worldBounds().lo.x(), lo.x(), "bounds lo");
    expectRel(dg.worldBounds().hi.z(), hi.z(), "bounds hi");
    EXPECT_GT(dg.info().active_tiles, 0);
    for (const auto& c : boxRays(b, h))
        expectRel(dg.integrate(c.r, c.t0, c.t1), 0.0028 * chord(b, c.r, c.t0, c.t1), c.name);
}

TEST(OpticalDepth, SoftEdgedAreaFromFogVolume)
{
    // sdfToFogVolume ramps density from 0 at the surface to the full value at depth edge: a ray
    // crossing two faces at right angles loses edge/2 of column at each.
    const double h = 0.02, edge = 0.2, rho = 0.003;
    const Vec3 lo(-0.99, -0.99, -0.99), hi(0.99, 0.99, 0.99);
    const DensityGrid dg = DensityGrid::box(lo, hi, rho, h, edge);
    EXPECT_NEAR(dg.maxValue(), rho, 1e-9);
    const Ray r{Vec3(-2, 0.013, -0.021), Vec3::UnitX()};
    const double want = rho * ((hi.x() - lo.x()) - edge);
    // Box filtering samples the ramp at voxel centres: exact for a linear ramp up to the voxel
    // that straddles the surface, so allow one voxel's worth of the ramp's slope at each face.
    EXPECT_NEAR(dg.integrate(r, 0, 10), want, 2 * rho * h * h / edge + 1e-9);
    EXPECT_GT(dg.info().active_tiles, 0);
}

TEST(OpticalDepth, LinearRamp)
{
    // value(i,j,k) = 0.01·i on i ∈ [0, 99]: box filtering integrates the staircase exactly,
    // trilinear reproduces the linear function exactly away from the ramp's ends.
    auto g = makeGrid(0.5, {0, 0, 0});
    auto acc = g->getAccessor();
    for (int i = 0; i < 100; ++i)
        for (int j = -10; j <= 10; ++j)
            for (int k = -10; k <= 10; ++k) acc.setValueOn(openvdb::Coord(i, j, k), 0.01f * i);
    const DensityGrid dg = wrapFloatGrid(g);
    // Along +x from index x=10.25 to x=60.75 (world ×0.5): staircase Σ.
    const Ray rx = ray(Vec3(0, 0.1, -0.2), Vec3::UnitX());
    const double t0 = 10.25 * 0.5, t1 = 60.75 * 0.5;
    double stair = 0;  // cells [i-½, i+½) of value 0.01·float(i)
    for (int i = 10; i <= 61; ++i) {
        const double a = std::max(t0, (i - 0.5) * 0.5), b = std::min(t1, (i + 0.5) * 0.5);
        if (b > a) stair += double(0.01f * i) * (b - a);
    }
    expectRel(dg.integrate(rx, t0, t1), stair, "box ramp");
    // Diagonal inside the slab: trilinear integral of 0.01·x_index is analytic.
    const Ray rd = ray(Vec3(5.0, -3.0, -2.0), Vec3(1, 0.2, 0.15));
    const double s0 = 0.5, s1 = 20.0;
    auto xi = [&](double t) { return rd.at(t).x() / 0.5; };
    const double lin = 0.01 * 0.5 * (xi(s0) + xi(s1)) * (s1 - s0);
    EXPECT_NEAR(dg.integrate(rd, s0, s1, Reconstruction::Trilinear), lin, 1e-6 * lin);
    expectRel(dg.integrate(rd, s0, s1), reference(*g, rd, s0, s1), "box ramp diagonal");
}

namespace {

/// n random rays through the middle of the grid's bounds (origins two metres back, spread by
/// `spread` m), each with a random segment [t0, t0 + 4u]: look(ray, t0, t1).
template <class Look>
void forRandomRays(const DensityGrid& dg, std::mt19937& rng, int n, double spread, Look&& look)
{
    std::uniform_real_distribution<double> U(0, 1);
    const Aabb b = dg.worldBounds();
    const Vec3 c = 0.5 * (b.lo + b.hi);
    for (int k = 0; k < n; ++k) {
        const Vec3 d = Vec3(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5).normalized();
        const Vec3 o = c - 2.0 * d + spread * Vec3(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5);
        const double t0 = U(rng), t1 = t0 + 4 * U(rng);
        look(ray(o, d), t0, t1);
    }
}

}  // namespace

TEST(OpticalDepth, RandomGridAgainstReference)
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> U(0, 1);
    auto g = makeGrid(0.07, {0.11, -0.23, 0.37});
    auto acc = g->getAccessor();
    for (int i = -12; i < 20; ++i)
        for (int j = -9; j < 15; ++j)
            for (int k = -14; k < 10; ++k)
                if (U(rng) < 0.7) acc.setValueOn(openvdb::Coord(i, j, k), float(U(rng)));
    g->tree().fill(openvdb::CoordBBox(openvdb::Coord(24, 0, 0), openvdb::Coord(31, 7, 15)), 0.4f, true);
    const DensityGrid dg = wrapFloatGrid(g);
    forRandomRays(dg, rng, 300, 0.6, [&](const Ray& r, double t0, double t1) {
        expectRel(dg.integrate(r, t0, t1), reference(*g, r, t0, t1), "random ray");
        std::vector<ProfileSegment> prof;
        const double tau = dg.integrate(r, t0, t1, Reconstruction::Box, &prof);
        double from_prof = 0;
        for (const auto& s : prof) {
            EXPECT_GE(s.t0_m, t0 - 1e-12);
            EXPECT_LE(s.t1_m, t1 + 1e-12);
            from_prof += s.density * (s.t1_m - s.t0_m);
        }
        expectRel(from_prof, tau, "profile sums to tau");
    });
}

TEST(OpticalDepth, SparseLeavesWithoutTilesAgainstReference)
{
    // Smoke in half of the 8³ blocks of a 6 × 6 × 6-block region and no tiles: the walk steps over
    // the empty blocks inside the support by the leaf table alone (no tree). Every ray through the
    // region against the reference walk.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> U(0, 1);
    auto g = makeGrid(0.05, {-0.31, 0.17, 0.05});
    auto acc = g->getAccessor();
    int filled = 0;
    for (int bi = -3; bi < 3; ++bi)
        for (int bj = -3; bj < 3; ++bj)
            for (int bk = -3; bk < 3; ++bk) {
                if (U(rng) < 0.5) continue;
                ++filled;
                for (int i = 0; i < 8; ++i)
                    for (int j = 0; j < 8; ++j)
                        for (int k = 0; k < 8; ++k)
                            if (U(rng) < 0.6)
                                acc.setValueOn(openvdb::Coord(8 * bi + i, 8 * bj + j, 8 * bk + k), float(U(rng)));
            }
    ASSERT_GT(filled, 60);
    ASSERT_LT(filled, 160);  // empty blocks inside the support
    const DensityGrid dg = wrapFloatGrid(g);
    forRandomRays(dg, rng, 400, 1.2, [&](const Ray& r, double t0, double t1) {
        expectRel(dg.integrate(r, t0, t1), reference(*g, r, t0, t1), "sparse ray");
    });
}

TEST(OpticalDepth, TrilinearMatchesFineQuadrature)
{
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> U(0, 1);
    auto g = makeGrid(0.1, {0, 0, 0});
    auto acc = g->getAccessor();
    for (int i = 0; i < 16; ++i)
        for (int j = 0; j < 16; ++j)
            for (int k = 0; k < 16; ++k) acc.setValueOn(openvdb::Coord(i, j, k), float(U(rng)));
    const DensityGrid dg = wrapFloatGrid(g);
    auto cacc = g->getConstAccessor();
    for (int n = 0; n < 20; ++n) {
        const Vec3 d = Vec3(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5).normalized();
        const Ray r = ray(Vec3(0.75, 0.75, 0.75) - 1.5 * d, d);
        // Composite Simpson on a very fine grid: converges to the exact integral of the piecewise cubic.
        const int N = 200000;
        const double t0 = 0, t1 = 3.0, h = (t1 - t0) / N;
        double s = 0;
        for (int i = 0; i <= N; ++i) {
            const Vec3 p = r.at(t0 + i * h) / 0.1;
            const double f = openvdb::tools::BoxSampler::sample(cacc, openvdb::Vec3R(p.x(), p.y(), p.z()));
            s += f * (i == 0 || i == N ? 1 : (i % 2 ? 4 : 2));
        }
        s *= h / 3;
        EXPECT_NEAR(dg.integrate(r, t0, t1, Reconstruction::Trilinear), s, 1e-6 * s);
    }
}

TEST(OpticalDepth, FirstAboveFindsTheEdge)
{
    auto g = makeGrid(0.1, {0, 0, 0});
    g->tree().fill(openvdb::CoordBBox(openvdb::Coord(10, -5, -5), openvdb::Coord(30, 5, 5)), 0.5f, true);
    const DensityGrid dg = wrapFloatGrid(g);
    const Ray r = ray(Vec3(0, 0, 0), Vec3::UnitX());
    EXPECT_NEAR(dg.firstAbove(r, 0, 10, 0.4), 0.95, 1e-9);
    EXPECT_EQ(dg.firstAbove(r, 0, 10, 0.6), kInf);
    EXPECT_EQ(dg.firstAbove(r, 0, 0.9, 0.4), kInf);
}

TEST(OpticalDepth, LongRaysThroughADenseBlock)
{
    // A 64³ block of random values: chords cross up to ~190 voxels, several of the walker's
    // chunks. The grid's leaves fill their bounding box, so the walker finds them by its leaf
    // table; the same block plus one far-away voxel has a box too sparse for a table, and the
    // walker asks the tree instead. Both must match the reference, profile and first-above too.
    std::mt19937 rng(13);
    std::uniform_real_distribution<double> U(0, 1);
    auto g = makeGrid(0.05, {0.02, -0.31, 0.17});
    {
        auto acc = g->getAccessor();
        for (int i = 0; i < 64; ++i)
            for (int j = 0; j < 64; ++j)
                for (int k = 0; k < 64; ++k) acc.setValueOn(openvdb::Coord(i - 20, j + 3, k - 40), float(U(rng)));
    }
    auto sparse = g->deepCopy();
    sparse->tree().setValueOn(openvdb::Coord(3000, -2000, 1500), 0.5f);
    const DensityGrid dense_dg = wrapFloatGrid(g), sparse_dg = wrapFloatGrid(sparse);
    ASSERT_FALSE(dense_dg.impl().leaves.values.empty());
    ASSERT_TRUE(sparse_dg.impl().leaves.values.empty());

    const Aabb b = dense_dg.worldBounds();
    const Vec3 c = 0.5 * (b.lo + b.hi);
    const double threshold = 0.997;
    int above = 0;
    for (int n = 0; n < 60; ++n) {
        const Vec3 d = Vec3(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5).normalized();
        const Vec3 o = c - 6.0 * d + 0.8 * Vec3(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5);
        const Ray r = ray(o, d);
        const double t0 = 2.0 * U(rng), t1 = 12.0;
        const auto pieces = referencePieces(*g, r, t0, t1);
        double want = 0, first = kInf;
        for (const RefPiece& p : pieces) {
            want += p.v * (p.tb - p.ta);
            if (first == kInf && p.v >= threshold) first = p.ta;
        }
        above += first < kInf;
        for (const DensityGrid* dg : {&dense_dg, &sparse_dg}) {
            std::vector<ProfileSegment> prof;
            expectRel(dg->integrate(r, t0, t1, Reconstruction::Box, &prof), want, "long ray");
            double from_prof = 0, last = t0;
            for (const auto& s : prof) {
                EXPECT_GE(s.t0_m, last - 1e-12);  // ascending, not overlapping
                EXPECT_GT(s.t1_m, s.t0_m);
                last = s.t1_m;
                from_prof += s.density * (s.t1_m - s.t0_m);
            }
            EXPECT_LE(last, t1 + 1e-12);
            expectRel(from_prof, want, "profile of a long ray");
            const double hit = dg->firstAbove(r, t0, t1, threshold);
            if (first == kInf)
                EXPECT_EQ(hit, kInf);
            else
                EXPECT_NEAR(hit, first, 1e-9);
        }
    }
    EXPECT_GT(above, 10);  // the threshold is met on many rays, often chunks into the walk
}
