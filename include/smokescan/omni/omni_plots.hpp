#pragma once
/// @file omni_plots.hpp
/// @brief The omnicam paper's figures from a run's frames: the histogram of the differences
/// between the laser and the omnicam (Fig. 9), and occupancy grids built from each sensor's scans
/// with the ground-truth poses, the laser's beside the omnicam's (Fig. 10).
///
/// | parameter | default | unit | meaning                                                   |
/// |-----------|---------|------|-----------------------------------------------------------|
/// | cell_m    | 0.03    | m    | occupancy grid cell                                       |
/// | range_m   | 8       | m    | laser beams drawn up to this (the omnicam: its own maximum) |
#include <string>
#include <vector>

#include "smokescan/omni/omni_run.hpp"
#include "smokescan/omni/range_tally.hpp"

namespace smokescan {

/// @brief Fig. 9: a histogram of `differences_m` (laser − omnicam, 5 cm bins over ±outlier_m)
/// with its mean and standard deviation, written as a PNG. @throw Error naming the file.
void writeDifferenceHistogram(const std::string& path, const std::vector<double>& differences_m, double outlier_m,
                              const std::string& title);

/// @brief Fig. 8: the floor distance d = h·tan(2·arctan(ρ/R)) against the pixel distance ρ from the
/// image centre, with one pixel's metric error d(ρ + 1) − d(ρ) (its hyperbolic growth), up to
/// max_range_m; written as a PNG. @throw Error naming the file.
void writePixelDistancePlot(const std::string& path, const OmniCamera& cam, double height_m, double max_range_m);

struct OccupancyConfig {
    double cell_m = 0.03;
    double range_m = 8.0;
};

/// @brief Fig. 10: two occupancy grids of the same area side by side, the laser's on the left and
/// the omnicam's on the right: cells the beams crossed are free (white), cells where they ended
/// on an obstacle occupied (black), the rest unknown (grey); the robot's path in red.
/// @throw Error naming the file; for an area over limits::kFramePixels cells.
void writeOccupancyGrids(const std::string& path, const std::vector<OmniFrame>& frames, const OccupancyConfig& cfg);

/// @brief The smoke drive's figure: for each sensor, the failure rate (top) and the mean |range
/// error| (bottom) against the smoke column it looked through, one line per sensor over the column
/// bins holding at least `min_readings` of its readings; written as a PNG.
/// @throw Error naming the file; for no tallies or tallies with different bins.
void writeVersusSmokePlot(const std::string& path, const std::vector<RangeTally>& tallies, const std::string& title,
                          long long min_readings = 20);

}  // namespace smokescan
