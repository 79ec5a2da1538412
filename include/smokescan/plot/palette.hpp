#pragma once
/// @file palette.hpp
/// @brief The colours of the report plots: a surface that names a colour is drawn in it
/// (blue, yellow, gold paper), others from a fixed palette by index.
#include <cstddef>
#include <string>

#include "smokescan/plot/canvas.hpp"

namespace smokescan {

/// @brief The colour for a surface or patch `name`, the `index`-th of its plot.
Col colourOf(const std::string& name, size_t index);

}  // namespace smokescan
