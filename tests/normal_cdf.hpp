#pragma once
// The standard normal's CDF for the tests, from its definition (not the library's).
#include <cmath>

namespace smokescan::test {

/// @brief Φ(z) = P(Z ≤ z) for a standard normal Z.
inline double normalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

}  // namespace smokescan::test
