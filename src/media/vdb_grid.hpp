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

    /// Validates `grid` (finite, non-negative values, zero background, uniform non-singular
    /// linear transform) and caches what the walkers need. `where` names the source for errors.
    static std::shared_ptr<Impl> make(openvdb::FloatGrid::Ptr grid, const std::string& where,
                                      const std::string& source_type = "float");
};

/// Calls openvdb::initialize() once.
void ensureOpenVdb();

/// Wraps a FloatGrid already in memory (tests and builders).
DensityGrid wrapFloatGrid(openvdb::FloatGrid::Ptr grid, const std::string& where = "grid");

}  // namespace smokescan
