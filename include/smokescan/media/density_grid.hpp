#pragma once
/// @file density_grid.hpp
/// @brief A smoke density grid (an OpenVDB FloatGrid behind a light handle) and the exact
/// line integral of its density along a ray.
///
/// Grid values are smoke density in the scene's density unit; a Medium turns density into
/// extinction σ_t [1/m]. The line integral ∫ρ ds [density·m] is the paper's "power consumed".
///
/// | reconstruction | what a voxel means                           | integral                    |
/// |----------------|----------------------------------------------|-----------------------------|
/// | Box (default)  | constant over its cube [i-½, i+½)³ (index)   | exact: one DDA step a voxel |
/// | Trilinear      | linear between voxel centres                 | exact: 2-point Gauss–Legendre per cell |
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "smokescan/core/ray.hpp"

namespace smokescan {

enum class Reconstruction { Box, Trilinear };

/// One piece of a density profile along a beam: density ρ on [t0_m, t1_m).
struct ProfileSegment {
    double t0_m = 0, t1_m = 0;
    double density = 0;  ///< mean density on the segment (exact for Box)
};

/// Summary of a grid, for `smokescan volume info`.
struct GridInfo {
    std::string name;
    std::string source_type;  ///< value type as stored in the file ("float", "double")
    double voxel_size_m = 0;
    long long active_voxels = 0;
    long long leaf_nodes = 0;
    long long active_tiles = 0;
    int index_min[3] = {0, 0, 0}, index_max[3] = {0, 0, 0};  ///< support of non-zero values
    Aabb world_bounds;
    double min_value = 0, max_value = 0;
    size_t memory_bytes = 0;
};

/// Options for reading a grid written by another tool.
struct VdbLoadConfig {
    std::string grid_name = "density";  ///< grid to read; "" takes the first scalar grid
    double scale = 1.0;  ///< stored value × scale = smoke density
};

class DensityGrid {
public:
    struct Impl;
    explicit DensityGrid(std::shared_ptr<const Impl> impl);
    ~DensityGrid();

    /// @brief Reads a float or double scalar grid from a .vdb file; honours the file's transform.
    /// @throw Error naming the file and the problem (missing file or grid, vector grid, NaN,
    ///        infinite or negative values, non-uniform or singular transform, non-zero background).
    static DensityGrid loadVdb(const std::string& path, const VdbLoadConfig& cfg = {});

    /// @brief A homogeneous axis-aligned box [lo, hi] (world metres) of density `value`,
    /// voxelised as a closed mesh (see fromMesh), interior kept as tiles.
    static DensityGrid box(const Vec3& lo_m, const Vec3& hi_m, double value, double voxel_size_m, double edge_m = 0.0);

    /// @brief A closed triangle mesh filled with `value` by OpenVDB: meshToLevelSet, then
    /// - edge_m = 0: the interior mask (voxels whose centres are inside; a crisp, exactly
    ///   homogeneous area), or
    /// - edge_m > 0: sdfToFogVolume, density ramping linearly from 0 at the surface to `value`
    ///   at depth edge_m (a soft edge).
    /// Constant regions are kept as tiles.
    static DensityGrid fromMesh(const std::vector<Vec3>& points_m, const std::vector<std::array<int, 3>>& triangles,
                                double value, double voxel_size_m, double edge_m = 0.0);

    /// @brief Gaussian blobs summed into a grid (the plume rasteriser). Each blob: centre [m],
    /// standard deviation [m], peak density. Cut off at 3σ.
    struct Blob {
        Vec3 centre_m;
        double sigma_m;
        double peak;
    };
    static DensityGrid fromBlobs(const std::vector<Blob>& blobs, double voxel_size_m);

    /// @brief ∫ρ ds [density·m] along the ray for t in [t0_m, t1_m].
    /// @param profile if non-null, receives the non-zero pieces of the profile, in order.
    double integrate(const Ray& ray, double t0_m, double t1_m, Reconstruction recon = Reconstruction::Box,
                     std::vector<ProfileSegment>* profile = nullptr) const;

    /// @brief The first t in [t0_m, t1_m] where the (box-filtered) density reaches `threshold`;
    /// +inf when it never does.
    double firstAbove(const Ray& ray, double t0_m, double t1_m, double threshold) const;

    /// @brief Density at a world point (box or trilinear).
    double sample(const Vec3& p_m, Reconstruction recon = Reconstruction::Box) const;

    /// @brief World boxes of the tree's leaves and non-zero tiles with the largest value in each
    /// (box filtering: a box covers its voxels' cubes). Majorant grids are built from these.
    std::vector<std::pair<Aabb, double>> blockMaxima() const;

    /// @brief Smallest and largest density over every voxel whose cube meets the world box
    /// (exact for axis-aligned grids; for rotated ones over a superset, so still bounds).
    /// Returns false (and leaves the outputs alone) when that is more than `max_voxels` voxels.
    bool rangeIn(const Aabb& world_box, double& min_out, double& max_out, long long max_voxels = 4096) const;

    /// @brief A copy whose values are multiplied by `factor`.
    DensityGrid scaled(double factor) const;

    GridInfo info() const;
    const Aabb& worldBounds() const;
    double voxelSize() const;
    double maxValue() const;

    /// @brief Writes grids to a .vdb file (temporary file, then rename), each under its name.
    static void writeVdb(const std::string& path, const std::vector<std::pair<std::string, DensityGrid>>& grids);

    const Impl& impl() const { return *impl_; }

private:
    std::shared_ptr<const Impl> impl_;
};

}  // namespace smokescan
