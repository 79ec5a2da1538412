#pragma once
// The parametric bootstrap behind fitSensor's errors on S* and the clock offset (internal):
// both streams drawn afresh from the fitted model, then fitted as the data were (docs/fitting.md,
// "Errors").
#include <cstdint>
#include <vector>

#include "smokescan/core/random.hpp"
#include "threshold_fit.hpp"

namespace smokescan::detail {

/// The fitted model of one group that a replicate's error counts are drawn from.
struct GroupModel {
    double S_star = 0;  ///< saturation at which the group errs [0, 1]
    double width = 0;  ///< the sensor's own width; 0: a sharp step
    bool logistic = false;
    /// Sharp step: each beam's own threshold about S* (the beams' paths differ), else empty.
    std::vector<double> beam_offset;
};

/// @brief Each beam's own sharp threshold about the group's median: the midpoint between the
/// highest saturation at which it erred and the lowest at which it read, 0 where those overlap.
/// @param failed [scan][beam in group]: the reading failed
/// @param S_at_scan the smoothed saturation at each scan (NaN: outside the camera's span)
std::vector<double> beamThresholdSpread(const std::vector<std::vector<bool>>& failed,
                                        const std::vector<double>& S_at_scan);

/// @brief Draws a replicate's error counts at the true saturation of each scan (NaN: the scan's
/// counts are kept): a sharp group's beams switch at their own thresholds, a smooth group's
/// beams err independently with the model's probability.
void drawErrorCounts(const GroupModel& m, const std::vector<double>& S_true, KeyedRng& rng, GroupCounts& c);

/// @brief A key for the replicates' random numbers from the data themselves (FNV-1a over the
/// saturation and the error counts): deterministic, and different for each run.
uint64_t dataKey(const std::vector<double>& saturation, const std::vector<const std::vector<int>*>& counts);

/// @brief The sample standard deviation of the finite values; NaN when fewer than `min_n`.
double finiteSpread(const std::vector<double>& v, int min_n);

}  // namespace smokescan::detail
