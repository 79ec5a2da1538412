#pragma once
// Internal: the diagnosis' test of a held-out gain (docs/diagnosis.md, "Held out").
#include <cstdint>
#include <vector>

namespace smokescan::detail {

/// @brief One-sided sign-flip p-value: the share of sign assignments of the units' gains whose
/// sum is at least the observed total. Exact over all 2^n assignments for n ≤ 20 nonzero gains,
/// else from `flips` random assignments (seeded; the observed one counted).
double signFlipP(const std::vector<double>& gains, long long flips, uint64_t seed);

}  // namespace smokescan::detail
