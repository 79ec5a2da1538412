#pragma once
/// @file order_stats.hpp
/// @brief Median and quantiles of a sample, one definition for the whole library.
#include <vector>

namespace smokescan {

/// @brief Median of v: the middle value, or the mean of the two middle values when the count is
/// even (v must hold no NaN). @return NaN when v is empty.
double median(std::vector<double> v);

/// @brief The q-quantile of v (q clamped to [0, 1]), interpolated linearly between order
/// statistics (Hyndman & Fan type 7, R's and NumPy's default): quantile(v, 0.5) = median(v).
/// v must hold no NaN. @return NaN when v is empty.
double quantile(std::vector<double> v, double q);

}  // namespace smokescan
