#pragma once
// Helpers for tests that write scene files as text.
#include <iomanip>
#include <sstream>
#include <string>

namespace smokescan::test {

/// A number as TOML text that parses back to the same double (17 significant digits).
inline std::string tomlNumber(double v)
{
    std::ostringstream o;
    o << std::setprecision(17) << v;
    return o.str();
}

}  // namespace smokescan::test
