#pragma once
/// @file format.hpp
/// @brief printf-style number formatting into a std::string, for plot labels and messages.
#include <cstdio>
#include <string>

namespace smokescan {

/// @brief `format` (a printf format) applied to `args`, at any length.
template <class... Args>
std::string fmt(const char* format, Args... args)
{
    char buf[256];
    const int n = std::snprintf(buf, sizeof buf, format, args...);
    if (n < 0) return {};
    if (size_t(n) < sizeof buf) return std::string(buf, size_t(n));
    std::string out(size_t(n) + 1, '\0');
    std::snprintf(out.data(), out.size(), format, args...);
    out.resize(size_t(n));
    return out;
}

}  // namespace smokescan
