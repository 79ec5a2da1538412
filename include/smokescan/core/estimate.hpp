#pragma once
/// @file estimate.hpp
/// @brief A fitted value and its standard error, the currency of every fit's result.
#include <cmath>

namespace smokescan {

/// A fitted value and its standard error (NaN when not determined), in the value's unit.
struct Estimate {
    double value = NAN, se = NAN;
};

}  // namespace smokescan
