#pragma once
/// @file format.hpp
/// @brief printf-style number formatting into a std::string, for plot labels and messages.
#include <cstdio>
#include <string>

namespace smokescan {

/// @brief `format` (a printf format with numeric conversions) applied to `args`.
template <class... Args>
std::string fmt(const char* format, Args... args)
{
    char buf[256];
    std::snprintf(buf, sizeof buf, format, args...);
    return buf;
}

}  // namespace smokescan
