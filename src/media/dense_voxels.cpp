#include "smokescan/media/dense_voxels.hpp"

#include <cmath>

#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"
#include "vdb_grid.hpp"

namespace smokescan {
namespace {

std::string voxelName(long long a, long long b, long long c)
{
    return "[" + std::to_string(a) + ", " + std::to_string(b) + ", " + std::to_string(c) + "]";
}

}  // namespace

DenseVoxels toDense(const DensityGrid& grid, const std::string& where)
{
    const DensityGrid::Impl& g = grid.impl();
    DenseVoxels d;
    const bool empty = g.support.empty();
    const openvdb::Coord lo = empty ? openvdb::Coord(0, 0, 0) : g.support.min(),
                         dim = empty ? openvdb::Coord(0, 0, 0) : g.support.dim();
    long long n = 1;
    for (int i = 0; i < 3; ++i) {
        d.size[size_t(i)] = dim[i];
        n *= dim[i];
        if (n > limits::kDenseVoxels)
            throw Error(where,
                        "its non-zero values span " + voxelName(dim[0], dim[1], dim[2]) + " voxels, over the " +
                            std::to_string(limits::kDenseVoxels) + " a dense block may hold");
    }
    d.values.assign(size_t(n), 0.0f);
    const auto acc = g.grid->getConstAccessor();
    size_t i = 0;
    for (long long a = 0; a < d.size[0]; ++a)
        for (long long b = 0; b < d.size[1]; ++b)
            for (long long c = 0; c < d.size[2]; ++c, ++i)
                d.values[i] = acc.getValue(lo + openvdb::Coord(int(a), int(b), int(c)));
    // world = A·(lo + (a, b, c)) + o, with A and o measured from the grid's own transform.
    const openvdb::math::Transform& xf = g.grid->transform();
    const openvdb::Vec3d o = xf.indexToWorld(openvdb::Vec3d(lo.x(), lo.y(), lo.z()));
    for (int col = 0; col < 3; ++col) {
        openvdb::Vec3d e(lo.x(), lo.y(), lo.z());
        e[col] += 1;
        const openvdb::Vec3d w = xf.indexToWorld(e) - o;
        for (int row = 0; row < 3; ++row) d.index_to_world[size_t(4 * row + col)] = w[row];
    }
    for (int row = 0; row < 3; ++row) d.index_to_world[size_t(4 * row + 3)] = o[row];
    return d;
}

DensityGrid fromDense(const DenseVoxels& d, const std::string& where)
{
    ensureOpenVdb();
    long long n = 1;
    for (long long s : d.size) {
        if (s < 0 || s > limits::kDenseVoxels) throw Error(where, "a dense block's sides must lie in 0…2^28");
        n *= s;
        if (n > limits::kDenseVoxels)
            throw Error(where,
                        "holds " + voxelName(d.size[0], d.size[1], d.size[2]) + " voxels, over the " +
                            std::to_string(limits::kDenseVoxels) + " a dense block may hold");
    }
    if (d.values.size() != size_t(n)) throw Error(where, "its values do not fill its size");
    const auto& m = d.index_to_world;
    for (double v : m)
        if (!std::isfinite(v)) throw Error(where, "its index-to-world map is not finite");
    if (m[12] != 0 || m[13] != 0 || m[14] != 0 || m[15] != 1)
        throw Error(where, "its index-to-world map is not affine (its last row must be 0 0 0 1)");
    openvdb::math::Mat4d mat;  // OpenVDB's maps act on row vectors: the transpose of ours
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) mat(c, r) = m[size_t(4 * r + c)];
    openvdb::math::Transform::Ptr xf;
    try {
        xf = openvdb::math::Transform::createLinearTransform(mat);
    } catch (const std::exception& e) {
        throw Error(where, std::string("its index-to-world map is not a transform (") + e.what() + ")");
    }
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setTransform(xf);
    grid->setName("density");
    auto acc = grid->getAccessor();
    size_t i = 0;
    for (long long a = 0; a < d.size[0]; ++a)
        for (long long b = 0; b < d.size[1]; ++b)
            for (long long c = 0; c < d.size[2]; ++c, ++i) {
                const float v = d.values[i];
                if (!std::isfinite(v) || v < 0 || v > limits::kDensity)
                    throw Error(where,
                                "voxel " + voxelName(a, b, c) + " holds " + std::to_string(v) +
                                    " (densities are finite, >= 0 and at most 1e6)");
                if (v != 0) acc.setValue(openvdb::Coord(int(a), int(b), int(c)), v);
            }
    grid->pruneGrid(0.0f);
    return DensityGrid(DensityGrid::Impl::make(grid, where));
}

}  // namespace smokescan
