#pragma once
/// @file plume.hpp
/// @brief Local smoke (the paper's particle smoke): particles from a point source, each a
/// Gaussian puff that rises, drifts with the wind, spreads and grows; rasterised into a VDB
/// density grid at any time. Particle k is born at start_s + k/rate_per_s and its random
/// velocity is a pure function of (seed, k), so a time's grid does not depend on which other
/// times were simulated.
///
/// | parameter        | default     | unit        | meaning                                         |
/// |------------------|-------------|-------------|-------------------------------------------------|
/// | source_m         | (0,0,0)     | m           | emission point                                  |
/// | rate_per_s       | 4           | 1/s         | particles emitted per second                    |
/// | lifetime_s       | 20          | s           | a particle vanishes at this age                 |
/// | rise_m_s         | 0.2         | m/s         | buoyant rise speed (+z)                         |
/// | wind_m_s         | (0,0,0)     | m/s         | drift of every particle                          |
/// | spread_m_s       | 0.05        | m/s         | std. dev. of each particle's own velocity, per axis |
/// | radius_m         | 0.15        | m           | Gaussian σ of a puff at birth                   |
/// | growth_m_s       | 0.05        | m/s         | σ grows linearly with age                        |
/// | peak_density     | 0.05        | density     | centre density at birth; mass is conserved as σ grows (peak ∝ σ⁻³) |
/// | start_s, stop_s  | 0, +inf     | s           | emission window                                  |
/// | voxel_m          | 0.1         | m           | voxel size of the rasterised grid               |
/// | seed             | 1           | –           | random seed                                      |
#include <cstdint>
#include <limits>

#include "smokescan/media/density_grid.hpp"

namespace smokescan {

struct PlumeConfig {
    Vec3 source_m = Vec3::Zero();
    double rate_per_s = 4.0;
    double lifetime_s = 20.0;
    double rise_m_s = 0.2;
    Vec3 wind_m_s = Vec3::Zero();
    double spread_m_s = 0.05;
    double radius_m = 0.15;
    double growth_m_s = 0.05;
    double peak_density = 0.05;
    double start_s = 0.0;
    double stop_s = std::numeric_limits<double>::infinity();
    double voxel_m = 0.1;
    uint64_t seed = 1;

    /// @throw Error naming the bad parameter.
    void validate() const;
    /// @brief Voxels its live puffs may cover at once (each a cube of 6σ a side at its widest):
    /// the work of rasterising it at one instant, which validate() and a scene bound.
    double voxelBound() const;
};

/// @brief The puffs alive at time t_s (centre, σ, peak density).
std::vector<DensityGrid::Blob> plumeBlobs(const PlumeConfig& cfg, double t_s);

/// @brief The plume's density grid at time t_s.
DensityGrid rasterisePlume(const PlumeConfig& cfg, double t_s);

}  // namespace smokescan
