#pragma once
/// @file cloud_profile.hpp
/// @brief Where a laser's readings fall across the smoke clouds (local smoke) its scans cross:
/// the measure behind the smoke paper's Fig. 10 claim that the Sick "sees smoke clouds as
/// obstacles in most cases", with error values "at the clouds' edges".
///
/// A cloud crossing is a run of consecutive beams of one scan whose local smoke column (up to the
/// surface, or the maximum range) is at least `min_column`. Its column profile across the run
/// peaks somewhere; the run's **core** is the beams whose column is at least `core_fraction` of
/// that peak and at least `core_min_column`, its **edge** the rest (the outer part of the profile,
/// where the smoke is thin and turbulent; a dissolving cloud thinner than `core_min_column`
/// everywhere is all edge). Each beam's reading is an obstacle (a range more than `obstacle_margin_m` short of
/// the surface, or any range when no surface is in range), the surface, or an error value.
///
/// | parameter         | default | unit      | meaning                                         |
/// |-------------------|---------|-----------|-------------------------------------------------|
/// | min_column        | 0.001   | density·m | a beam at least this deep in local smoke is in a cloud |
/// | core_fraction     | 0.5     | –         | core: column ≥ this × the run's peak column     |
/// | core_min_column   | 0.005   | density·m | core: column at least this (the paper model's local threshold 0.002 × 2.5 m) |
/// | obstacle_margin_m | 0.3     | m         | an obstacle reads at least this short of the surface |
#include <map>
#include <string>
#include <utility>

#include "smokescan/sensors/scanner.hpp"

namespace smokescan {

struct CloudProfileConfig {
    double min_column = 0.001;
    double core_fraction = 0.5;
    double core_min_column = 0.005;
    double obstacle_margin_m = 0.3;
};

/// Counts of readings in the clouds' cores and edges.
struct CloudProfileResult {
    CloudProfileConfig config;  ///< what core and edge meant
    long long runs = 0;  ///< cloud crossings (runs of beams)
    long long core_beams = 0, core_obstacles = 0, core_errors = 0;
    long long edge_beams = 0, edge_obstacles = 0, edge_errors = 0;
    /// Error values by cause (BeamResult::cause): (in cores, at edges).
    std::map<std::string, std::pair<long long, long long>> error_causes;

    /// Share of the cores' beams that read an obstacle.
    double coreObstacleShare() const;
    /// Error rate in the cores and at the edges.
    double coreErrorRate() const;
    double edgeErrorRate() const;
    /// Share of all error values inside clouds that lie at the edges, and the edges' share of the
    /// beams: errors concentrate at the edges when the first exceeds the second.
    double errorShareAtEdges() const;
    double edgeShareOfBeams() const;
    /// @brief A summary: obstacles and errors in cores and at edges, the errors' causes.
    std::string text() const;
};

/// Accumulates scans (with their beams kept) into a CloudProfileResult.
class CloudProfile {
public:
    explicit CloudProfile(CloudProfileConfig cfg = {}) : cfg_(cfg) { r_.config = cfg; }
    /// @brief Adds one scan's cloud crossings.
    void add(const Scan& s);
    const CloudProfileResult& result() const { return r_; }

private:
    CloudProfileConfig cfg_;
    CloudProfileResult r_;
};

}  // namespace smokescan
