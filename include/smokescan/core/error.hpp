#pragma once
/// @file error.hpp
/// @brief The one exception type smokescan throws for bad input: its message is the one-line
/// error the CLI prints ("FILE[:LINE]: problem").
#include <stdexcept>
#include <string>

namespace smokescan {

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& what) : std::runtime_error(what) {}
    /// @param where file (and optionally ":line" or key) the problem is in
    Error(const std::string& where, const std::string& problem)
        : std::runtime_error(where.empty() ? problem : where + ": " + problem) {}
};

}  // namespace smokescan
