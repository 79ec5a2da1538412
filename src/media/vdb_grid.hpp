#pragma once
// Internal: the OpenVDB side of DensityGrid. Only media/*.cpp (and white-box tests) include this.
#include <openvdb/openvdb.h>

#include <Eigen/Core>

#include "smokescan/media/density_grid.hpp"

namespace smokescan {

struct DensityGrid::Impl {
    openvdb::FloatGrid::Ptr grid;
    std::string source_type = "float";
    Eigen::Matrix3d w2i_lin = Eigen::Matrix3d::Identity();  ///< index = w2i_lin·world + w2i_off
    Eigen::Vector3d w2i_off = Eigen::Vector3d::Zero();
    double voxel_size_m = 1;
    openvdb::CoordBBox support;  ///< index bbox of all non-zero values (voxels and tiles)
    Aabb world_bounds;
    double min_value = 0, max_value = 0;
    /// Whether the box walker may step over a cell in no leaf as its empty 8³ block from the leaf
    /// table alone, without the tree: no tile holds a non-zero value (a cell in no leaf holds 0)
    /// and the table spans at most kMaxEmptyBlocksAxis blocks an axis (a line crosses few of them;
    /// the tree steps over a wider empty region at once).
    bool empty_blocks_by_table = false;
    static constexpr int kMaxEmptyBlocksAxis = 32;  ///< two of the tree's lower nodes

    /// Where each leaf's values are, by 8³ block over the leaves' bounding box: the box walker finds
    /// a leaf with one load from this small array, which it can prefetch ahead, instead of
    /// descending the tree, whose dependent node loads miss cache on a large grid and stall the
    /// walk. Empty (the walker then asks the tree) when the box would hold more than
    /// kMaxBlocksPerLeaf blocks per leaf.
    struct LeafTable {
        static constexpr long long kMaxBlocksPerLeaf = 8;  ///< ≤ 64 B of table per 2 KB leaf
        openvdb::Coord lo;  ///< lowest block (leaf origin / 8)
        int n[3] = {0, 0, 0};  ///< blocks along x, y, z
        std::vector<const float*> values;  ///< x-major; nullptr: no leaf there
    } leaves;

    /// Validates `grid` (finite, non-negative values, zero background, uniform non-singular
    /// linear transform) and caches what the walkers need. `where` names the source for errors.
    static std::shared_ptr<Impl> make(openvdb::FloatGrid::Ptr grid, const std::string& where,
                                      const std::string& source_type = "float");
};

/// Calls openvdb::initialize() once.
void ensureOpenVdb();

/// Wraps a FloatGrid already in memory (tests and builders). The grid must not change afterwards:
/// the wrapper caches its support, value range and the addresses of its leaves' values.
DensityGrid wrapFloatGrid(openvdb::FloatGrid::Ptr grid, const std::string& where = "grid");

}  // namespace smokescan
