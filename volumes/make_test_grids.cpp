// Makes the small grids the tests read (volumes/*.vdb), with OpenVDB directly, so that the
// loader meets files smokescan did not write itself: a float grid and a double grid, each with
// a density whose line integrals are known in closed form. Run by volumes/make_test_grids.sh.
#include <openvdb/openvdb.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace {

/// A fog ball: density ρ(r) = 1 − (r/R)² inside radius R = 0.2 m, voxel 0.01 m, centred at the
/// origin (voxel centres at integer index × 0.01 m). Column through the centre: 4R/3 density·m.
openvdb::FloatGrid::Ptr fogBall()
{
    const double h = 0.01;
    const int n = 20;  // R = n·h = 0.2 m
    auto g = openvdb::FloatGrid::create(0.f);
    g->setName("density");
    g->setTransform(openvdb::math::Transform::createLinearTransform(h));
    g->setGridClass(openvdb::GRID_FOG_VOLUME);
    auto acc = g->getAccessor();
    for (int i = -n; i <= n; ++i)
        for (int j = -n; j <= n; ++j)
            for (int k = -n; k <= n; ++k) {
                const int r2 = i * i + j * j + k * k;  // in voxels², exact
                if (r2 < n * n) acc.setValue(openvdb::Coord(i, j, k), float(1.0 - double(r2) / (n * n)));
            }
    return g;
}

/// A dense 32 × 16 × 16 block of doubles, voxel 0.05 m, index [0,31]×[0,15]×[0,15]: value
/// (i + 1) / 32 in column i, so a ray along x crosses Σ (i+1)/32 × 0.05 = 0.825 density·m.
openvdb::DoubleGrid::Ptr rampBlock()
{
    auto g = openvdb::DoubleGrid::create(0.0);
    g->setName("density");
    g->setTransform(openvdb::math::Transform::createLinearTransform(0.05));
    g->setGridClass(openvdb::GRID_FOG_VOLUME);
    auto acc = g->getAccessor();
    for (int i = 0; i < 32; ++i)
        for (int j = 0; j < 16; ++j)
            for (int k = 0; k < 16; ++k) acc.setValue(openvdb::Coord(i, j, k), (i + 1) / 32.0);
    return g;
}

void write(const std::string& path, openvdb::GridBase::Ptr g)
{
    openvdb::io::File f(path);
    f.setCompression(openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK);
    f.write({g});
    f.close();
    std::printf("wrote %s\n", path.c_str());
}

}  // namespace

int main(int argc, char** argv)
{
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUTPUT_FOLDER\n", argv[0]);
        return 2;
    }
    openvdb::initialize();
    const std::string dir = argv[1];
    write(dir + "/fog_ball_float.vdb", fogBall());
    write(dir + "/ramp_block_double.vdb", rampBlock());
    return 0;
}
