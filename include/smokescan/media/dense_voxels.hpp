#pragma once
/// @file dense_voxels.hpp
/// @brief A density grid to and from a dense block of voxels with its transform: what numpy
/// holds of a volume (the Python module's read_volume and write_volume).
///
/// | field          | meaning                                                               |
/// |----------------|-----------------------------------------------------------------------|
/// | size           | voxels along the block's axes a, b, c                                  |
/// | values         | density [the scene's density unit] of voxel (a, b, c) at (a·size[1] + b)·size[2] + c |
/// | index_to_world | row-major 4 × 4 affine map: world [m] = M · (a, b, c, 1), a voxel's centre |
///
/// Voxels are cubes (the map's linear part a rotation times the voxel size) and each voxel's
/// density is constant over its cube (the box reconstruction, media/density_grid.hpp).
#include <array>
#include <string>
#include <vector>

#include "smokescan/media/density_grid.hpp"

namespace smokescan {

struct DenseVoxels {
    std::array<long long, 3> size{0, 0, 0};
    std::vector<float> values;
    std::array<double, 16> index_to_world{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
};

/// @brief The grid's voxels over the index box of its non-zero values, with the map from the
/// block's indices to world metres (an empty grid: an empty block, the map of its index origin).
/// @throw Error naming `where` when the box holds more than limits::kDenseVoxels voxels.
DenseVoxels toDense(const DensityGrid& grid, const std::string& where);

/// @brief A grid from a dense block: its non-zero voxels active, zeros the background.
/// @throw Error naming `where` for a size that does not match the values or is over
/// limits::kDenseVoxels, a value that is negative, not finite or over limits::kDensity (naming the
/// voxel), or a map that is
/// not affine, not finite, singular or not uniform (voxels must be cubes).
DensityGrid fromDense(const DenseVoxels& dense, const std::string& where);

}  // namespace smokescan
