// The VDB loader on files made by other tools, the writer, and every bad grid it must refuse.
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <sstream>

#include "../src/media/vdb_grid.hpp"
#include "../src/media/vdb_header.hpp"
#include "smokescan/core/error.hpp"

#include "error_of.hpp"
#include "scratch.hpp"
#include "test_data.hpp"

using namespace smokescan;
using smokescan::test::errorOf;
namespace fs = std::filesystem;

namespace {

fs::path tmpDir() { return smokescan::test::scratch("vdb_io"); }

std::string writeGrid(const std::string& name, openvdb::GridBase::Ptr g)
{
    const std::string p = (tmpDir() / name).string();
    openvdb::io::File f(p);
    f.write({g});
    f.close();
    return p;
}

}  // namespace

TEST(VdbLoad, FogBallOfKnownColumns)
{
    // volumes/fog_ball_float.vdb: ρ = 1 − (r/R)², R = 0.2 m, voxels of 0.01 m centred on integer
    // indices. Through the centre the column is 4R/3; off-centre at distance b, 4(R² − b²)^{3/2}/(3R²).
    const DensityGrid g = DensityGrid::loadVdb(test::projectVolume("fog_ball_float.vdb"));
    const GridInfo i = g.info();
    EXPECT_EQ(i.source_type, "float");
    EXPECT_NEAR(i.voxel_size_m, 0.01, 1e-12);
    EXPECT_EQ(i.index_min[0], -19);
    EXPECT_EQ(i.index_max[2], 19);
    const double R = 0.2;
    for (double b : {0.0, 0.063, 0.12}) {
        const Ray r{Vec3(-1, b, 0.0), Vec3::UnitX()};
        const double want = 4 * std::pow(R * R - b * b, 1.5) / (3 * R * R);
        // Box reconstruction on a 1 cm grid: the voxelised ball differs from the analytic one by
        // at most about a voxel's worth of the column's slope.
        EXPECT_NEAR(g.integrate(r, 0, 2), want, 0.02 * want + 0.002) << "b = " << b;
    }
}

TEST(VdbLoad, RampBlockOfDoubles)
{
    // volumes/ramp_block_double.vdb: a DoubleGrid, value (i+1)/32 in index column i, voxel 0.05 m.
    const DensityGrid g = DensityGrid::loadVdb(test::projectVolume("ramp_block_double.vdb"), {"density", 2.0});
    const GridInfo i = g.info();
    EXPECT_EQ(i.source_type, "double");
    EXPECT_EQ(i.active_voxels, 32 * 16 * 16);
    EXPECT_NEAR(i.max_value, 2.0, 1e-6);
    const Ray r{Vec3(-1, 0.37, 0.41), Vec3::UnitX()};  // inside the block's index y, z range
    EXPECT_NEAR(g.integrate(r, 0, 4), 2.0 * 0.05 * (32 * 33 / 2) / 32.0, 1e-9);
}

TEST(VdbLoad, TeapotCloudFromPbrtVolumes)
{
    SMOKESCAN_EXTERNAL_VDB_OR_SKIP(p, "teapot_cloud.vdb");
    const DensityGrid g = DensityGrid::loadVdb(p);
    const GridInfo i = g.info();
    EXPECT_EQ(i.source_type, "float");
    EXPECT_NEAR(i.voxel_size_m, 0.00767, 1e-5);
    EXPECT_EQ(i.active_voxels, 1963736);  // as vdb_print reports
    EXPECT_EQ(i.active_tiles, 2326);
    EXPECT_EQ(i.index_min[0], -136);
    EXPECT_EQ(i.index_max[0], 130);
    EXPECT_NEAR(i.max_value, 50.0, 0.5);
    // A ray through the middle meets smoke; its column equals the sum of its profile.
    const Vec3 c = 0.5 * (g.worldBounds().lo + g.worldBounds().hi);
    const Ray r{c - Vec3(2, 0, 0), Vec3::UnitX()};
    std::vector<ProfileSegment> prof;
    const double col = g.integrate(r, 0, 4, Reconstruction::Box, &prof);
    EXPECT_GT(col, 0.0);
    double s = 0;
    for (auto& q : prof) s += q.density * (q.t1_m - q.t0_m);
    EXPECT_NEAR(s, col, 1e-9 * col);
}

TEST(VdbLoad, DenseDoubleGridOlderFormat)
{
    SMOKESCAN_EXTERNAL_VDB_OR_SKIP(p, "smoke_dense_double.vdb");
    const DensityGrid g = DensityGrid::loadVdb(p, {"density", 2.0});
    const GridInfo i = g.info();
    EXPECT_EQ(i.source_type, "double");
    EXPECT_LE(i.index_max[0] - i.index_min[0] + 1, 128);
    EXPECT_LE(i.max_value, 2.0 + 1e-6);  // values 0…1, scaled by 2
    EXPECT_GT(i.max_value, 0.5);
}

TEST(VdbLoad, WriteBackRoundTripsAndOpensInVdbPrint)
{
    const DensityGrid g = DensityGrid::loadVdb(test::projectVolume("ramp_block_double.vdb"));
    const std::string out = (tmpDir() / "roundtrip.vdb").string();
    DensityGrid::writeVdb(out, {{"smoke", g}});
    const DensityGrid h = DensityGrid::loadVdb(out, {"smoke", 1.0});
    const Vec3 c = 0.5 * (g.worldBounds().lo + g.worldBounds().hi);
    const Ray r{c - Vec3(0, 0, 2), Vec3(0.1, 0.2, 1).normalized()};
    EXPECT_GT(g.integrate(r, 0, 4), 0.1);
    EXPECT_DOUBLE_EQ(g.integrate(r, 0, 4), h.integrate(r, 0, 4));
    if (std::system("command -v vdb_print >/dev/null 2>&1") == 0)
        EXPECT_EQ(std::system(("vdb_print " + out + " >/dev/null").c_str()), 0);
}

TEST(VdbLoad, BadInputsGiveOneLineErrors)
{
    ensureOpenVdb();
    EXPECT_NE(errorOf([] { DensityGrid::loadVdb("/nonexistent/x.vdb"); }).find("no such file"), std::string::npos);
    const std::string txt = (tmpDir() / "not_a_grid.vdb").string();
    {
        std::ofstream(txt) << "hello";
    }
    EXPECT_NE(errorOf([&] { DensityGrid::loadVdb(txt); }).find("not a valid VDB file: no VDB magic number"),
              std::string::npos);
    EXPECT_NE(errorOf([] {
                  DensityGrid::loadVdb(test::projectVolume("fog_ball_float.vdb"), {"temperature", 1});
              }).find("no grid named 'temperature' (grids: density)"),
              std::string::npos);

    auto vec = openvdb::Vec3SGrid::create();
    vec->setName("density");
    vec->tree().setValue(openvdb::Coord(0), openvdb::Vec3s(1));
    const std::string pv = writeGrid("vec.vdb", vec);
    EXPECT_NE(errorOf([&] { DensityGrid::loadVdb(pv); }).find("must be scalar float or double"), std::string::npos);

    auto bad = [&](const std::string& file, float value, const std::string& expect, bool nonuniform = false,
                   float bg = 0.f) {
        auto g = openvdb::FloatGrid::create(bg);
        g->setName("density");
        g->tree().setValue(openvdb::Coord(1, 2, 3), value);
        if (nonuniform) {
            auto xf = openvdb::math::Transform::createLinearTransform(1.0);
            xf->preScale(openvdb::Vec3d(1, 2, 1));
            g->setTransform(xf);
        }
        const std::string p = writeGrid(file, g);
        const std::string e = errorOf([&] { DensityGrid::loadVdb(p); });
        EXPECT_NE(e.find(expect), std::string::npos) << e;
        EXPECT_EQ(e.rfind(p, 0), 0u) << "error must start with the file name: " << e;
        EXPECT_EQ(e.find('\n'), std::string::npos);
    };
    bad("nan.vdb", std::nanf(""), "non-finite density");
    bad("inf.vdb", INFINITY, "non-finite density");
    bad("neg.vdb", -0.5f, "negative density");
    bad("nonuniform.vdb", 1.f, "non-uniform transform", true);
    bad("background.vdb", 1.f, "background", false, 0.1f);

    // A singular transform: OpenVDB will not build one, so write a ScaleMap of (1, 2.5, 1) and
    // zero the 2.5 in the file, as a corrupt or foreign writer might.
    auto g = openvdb::FloatGrid::create(0.f);
    g->setName("density");
    g->tree().setValue(openvdb::Coord(1, 2, 3), 1.f);
    auto xf = openvdb::math::Transform::createLinearTransform(1.0);
    xf->preScale(openvdb::Vec3d(1, 2.5, 1));
    g->setTransform(xf);
    const std::string ok = writeGrid("scaled.vdb", g);
    std::ifstream in(ok, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    const double from = 2.5, to = 0.0;
    int patched = 0;
    for (size_t i = 0; i + sizeof(double) <= bytes.size(); ++i)
        if (std::memcmp(&bytes[i], &from, sizeof from) == 0) {
            std::memcpy(&bytes[i], &to, sizeof to);
            ++patched;
        }
    ASSERT_GT(patched, 0);
    const std::string sing = (tmpDir() / "singular.vdb").string();
    std::ofstream(sing, std::ios::binary) << bytes;
    const std::string e = errorOf([&] { DensityGrid::loadVdb(sing); });
    EXPECT_NE(e.find("singular transform"), std::string::npos) << e;
}

namespace {
std::string bytesOf(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), {});
}

std::string headerError(const std::string& bytes)
{
    std::istringstream in(bytes);
    return errorOf([&] { detail::checkVdbHeader(in, bytes.size(), "x.vdb"); });
}
}  // namespace

// Damaged files are refused by the structure check, before OpenVDB reads them (an edited type
// string used to make OpenVDB spin; a truncated file or a huge string length to allocate GBs).
TEST(VdbHeader, RefusesDamagedFilesBeforeOpenVdbReadsThem)
{
    const std::string good = bytesOf(test::projectVolume("fog_ball_float.vdb"));
    ASSERT_GT(good.size(), 1000u);
    std::istringstream in(good);
    const auto grids = detail::checkVdbHeader(in, good.size(), "ball");
    ASSERT_EQ(grids.size(), 1u);
    EXPECT_EQ(grids[0].name, "density");
    EXPECT_EQ(grids[0].type, "float");
    EXPECT_EQ(grids[0].end_pos, int64_t(good.size()));
    EXPECT_EQ(grids[0].voxels, 33371);  // lattice points with i² + j² + k² < 20², from the grid's own metadata

    // Every truncation is refused, by the check alone.
    for (size_t n :
         {size_t(0), size_t(7), size_t(56), size_t(64), size_t(100), size_t(200), good.size() / 2, good.size() - 1})
        EXPECT_NE(headerError(good.substr(0, n)).find("not a valid VDB file"), std::string::npos) << n;

    // The type string edited (float → vec3s): refused with the loader's own message, at once.
    std::string vec = good;
    const auto at = vec.find("Tree_float_5_4_3");
    ASSERT_NE(at, std::string::npos);
    vec.replace(at, 16, "Tree_vec3s_5_4_3");
    const std::string pv = (tmpDir() / "edited_type.vdb").string();
    std::ofstream(pv, std::ios::binary) << vec;
    EXPECT_NE(errorOf([&] { DensityGrid::loadVdb(pv); }).find("holds vec3s values"), std::string::npos);
    vec.replace(at, 16, "Tree_vec9q_5_4_3");
    EXPECT_NE(headerError(vec).find("unknown type 'Tree_vec9q_5_4_3'"), std::string::npos);

    // A grid name's length set to 4 GB, and a negative grid count.
    std::string huge = good;
    const uint32_t len = 0xFFFFFFF0u;
    std::memcpy(&huge[at - 4 - 4 - 7], &len, 4);  // the name "density" and its length precede the type's
    EXPECT_NE(headerError(huge).find("a grid name of 4294967280 bytes"), std::string::npos) << headerError(huge);
    std::string neg = good;
    const int32_t minus = -1;
    std::memcpy(&neg[61], &minus, 4);  // after the 57-byte header and an empty file metadata count
    EXPECT_NE(headerError(neg).find("a grid count of -1"), std::string::npos) << headerError(neg);

    // Any single byte of the structure changed: refused or accepted, never a crash or a hang (the
    // sanitizer build runs this too).
    for (size_t i = 0; i < size_t(grids[0].grid_pos) + 64; ++i)
        for (unsigned char v : {0x00, 0x7F, 0xFF}) {
            std::string b = good;
            b[i] = char(v);
            (void)headerError(b);
        }
}
