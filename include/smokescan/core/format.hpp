#pragma once
/// @file format.hpp
/// @brief printf-style number formatting into a std::string, for messages and plot labels.
#include <cstdio>
#include <cstdlib>
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

/// @brief The shortest text that reads back as exactly `v` (%.{1..17}g): a time of the Unix epoch
/// keeps its fraction of a second, and 0.1 stays "0.1".
inline std::string shortest(double v)
{
    char buf[32];
    for (int p = 6; p <= 17; ++p) {
        std::snprintf(buf, sizeof buf, "%.*g", p, v);
        if (std::strtod(buf, nullptr) == v) break;
    }
    return buf;
}

/// @brief A TOML basic string: quoted, with quotes, backslashes and control characters escaped
/// (what a file the program writes names: a preset, a surface).
inline std::string tomlQuoted(const std::string& s)
{
    std::string o = "\"";
    for (const char ch : s) {
        const auto c = static_cast<unsigned char>(ch);
        if (c == '"' || c == '\\') {
            o += '\\';
            o += ch;
        } else if (c < 0x20 || c == 0x7f) {
            o += fmt("\\u%04x", unsigned(c));
        } else {
            o += ch;
        }
    }
    return o + "\"";
}

}  // namespace smokescan
