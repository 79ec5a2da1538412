#pragma once
/// @file smoke.hpp
/// @brief The scene's smoke: volumes (areas, plumes, loaded grids) with their media and
/// timelines, and the field they make at one time, queried per beam.
///
/// Overlapping volumes add: the column and the optical depth along a beam are the sums over
/// volumes of their exact integrals (each volume keeps its own grid and transform, so no
/// resampling error enters the sum).
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "smokescan/media/density_grid.hpp"
#include "smokescan/media/medium.hpp"
#include "smokescan/media/plume.hpp"
#include "smokescan/media/timeline.hpp"

namespace smokescan {

/// Regional smoke (the paper's SmokeRegional: areas that consume penetration power) or local
/// smoke (particle plumes, which the paper's model treats as solid).
enum class SmokeRole { Regional, Local };

struct SmokeVolume {
    std::string name;
    SmokeRole role = SmokeRole::Regional;
    Medium medium;
    DensityTimeline timeline = DensityTimeline::constant();
    /// A fixed grid (area from a mesh or box, or a loaded .vdb) or a plume rasterised per time.
    std::variant<std::shared_ptr<const DensityGrid>, PlumeConfig> source;
    std::string file;  ///< the mesh or .vdb file it was made from ("" for none)

    /// The grid at time t [s], before the timeline's scale.
    std::shared_ptr<const DensityGrid> gridAt(double t_s) const;
};

/// What a beam met between t0 and t1.
struct BeamSmoke {
    double column_regional = 0;  ///< ∫ρ ds over regional volumes [density·m]
    double column_local = 0;  ///< ∫ρ ds over local volumes [density·m]
    double tau = 0;  ///< optical depth ∫σ_t ds at the query wavelength, all volumes
    double first_local_m = kInf;  ///< first distance where local density ≥ the query threshold
    /// Non-zero pieces of σ_t(s) [1/m] at the query wavelength, all volumes summed (if asked).
    std::vector<ProfileSegment> sigma_t_profile;
    /// Non-zero pieces of the backscatter β(s) = σ_t·β/σ_t [1/(m·sr)], all volumes (if asked).
    std::vector<ProfileSegment> beta_profile;
};

struct BeamQuery {
    double wavelength_nm = 785.0;
    double local_threshold = kInf;  ///< density at which local smoke counts as met
    bool want_profile = false;  ///< fill sigma_t_profile and beta_profile
    Reconstruction recon = Reconstruction::Box;
};

/// The smoke of a scene frozen at one time.
class SmokeField {
public:
    struct Entry {
        const SmokeVolume* volume;
        std::shared_ptr<const DensityGrid> grid;
        double scale;  ///< timeline scale at this time
        double wavelength_nm = -1;  ///< the wavelength `sigma_t` was evaluated at (-1: none)
        double sigma_t = 0;  ///< the medium's σ_t at wavelength_nm [1/m per unit density]
        Aabb reach;  ///< the grid's world bounds and a voxel more: a beam that misses them meets no smoke of it
    };

    SmokeField() = default;
    /// Evaluates every volume's grid and scale at t_s (plumes are rasterised here).
    static SmokeField at(const std::vector<SmokeVolume>& volumes, double t_s);

    /// @brief Integrates the beam over [t0_m, t1_m].
    BeamSmoke trace(const Ray& ray, double t0_m, double t1_m, const BeamQuery& q) const;
    /// @brief The same into `out`, whose storage is reused (a frame's beams, one after another).
    void trace(const Ray& ray, double t0_m, double t1_m, const BeamQuery& q, BeamSmoke& out) const;

    const std::vector<Entry>& entries() const { return entries_; }

    /// @brief Evaluates each medium's σ_t at this wavelength once: beams traced at it then skip
    /// the spectral power law (the same values, sooner).
    void prepare(double wavelength_nm);

    /// @brief The same field with every regional volume's density multiplied by k (local plumes
    /// unchanged): columns through regional smoke scale by k exactly.
    SmokeField scaledRegional(double k) const;

private:
    std::vector<Entry> entries_;
};

/// Sums piecewise-constant profiles into one (breakpoints merged, zero pieces dropped).
std::vector<ProfileSegment> sumProfiles(const std::vector<std::vector<ProfileSegment>>& parts);
/// The same for parts[0, n_parts) into `out` (its storage reused).
void sumProfiles(const std::vector<ProfileSegment>* parts, size_t n_parts, std::vector<ProfileSegment>& out);

}  // namespace smokescan
