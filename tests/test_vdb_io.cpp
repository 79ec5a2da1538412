// The VDB loader on files made by other tools, the writer, and every bad grid it must refuse.
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <cstdlib>
#include <cstring>
#include <iterator>
#include <filesystem>
#include <fstream>
#include <functional>

#include "../src/media/vdb_grid.hpp"
#include "smokescan/core/error.hpp"

#include "scratch.hpp"

using namespace smokescan;
namespace fs = std::filesystem;

namespace {
const std::string kShared = std::string(SMOKESCAN_SOURCE_DIR) + "/../shared/data/vdb/";

fs::path tmpDir()
{
    return smokescan::test::scratch("vdb_io");
}

std::string writeGrid(const std::string& name, openvdb::GridBase::Ptr g)
{
    const std::string p = (tmpDir() / name).string();
    openvdb::io::File f(p);
    f.write({g});
    f.close();
    return p;
}

std::string errorOf(const std::function<void()>& f)
{
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(VdbLoad, TeapotCloudFromPbrtVolumes)
{
    const std::string p = kShared + "teapot_cloud.vdb";
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
    const DensityGrid g = DensityGrid::loadVdb(kShared + "smoke_dense_double.vdb", {"density", 2.0});
    const GridInfo i = g.info();
    EXPECT_EQ(i.source_type, "double");
    EXPECT_LE(i.index_max[0] - i.index_min[0] + 1, 128);
    EXPECT_LE(i.max_value, 2.0 + 1e-6);  // values 0…1, scaled by 2
    EXPECT_GT(i.max_value, 0.5);
}

TEST(VdbLoad, WriteBackRoundTripsAndOpensInVdbPrint)
{
    const DensityGrid g = DensityGrid::loadVdb(kShared + "smoke_dense_double.vdb");
    const std::string out = (tmpDir() / "roundtrip.vdb").string();
    DensityGrid::writeVdb(out, {{"smoke", g}});
    const DensityGrid h = DensityGrid::loadVdb(out, {"smoke", 1.0});
    const Vec3 c = 0.5 * (g.worldBounds().lo + g.worldBounds().hi);
    const Ray r{c - Vec3(0, 0, 50), Vec3(0.1, 0.2, 1).normalized()};
    EXPECT_DOUBLE_EQ(g.integrate(r, 0, 100), h.integrate(r, 0, 100));
    if (std::system("command -v vdb_print >/dev/null 2>&1") == 0)
        EXPECT_EQ(std::system(("vdb_print " + out + " >/dev/null").c_str()), 0);
}

TEST(VdbLoad, BadInputsGiveOneLineErrors)
{
    ensureOpenVdb();
    EXPECT_NE(errorOf([] { DensityGrid::loadVdb("/nonexistent/x.vdb"); }).find("no such file"), std::string::npos);
    const std::string txt = (tmpDir() / "not_a_grid.vdb").string();
    { std::ofstream(txt) << "hello"; }
    EXPECT_NE(errorOf([&] { DensityGrid::loadVdb(txt); }).find("cannot read"), std::string::npos);
    EXPECT_NE(errorOf([] { DensityGrid::loadVdb(kShared + "teapot_cloud.vdb", {"temperature", 1}); })
                  .find("no grid named 'temperature' (grids: density)"),
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
