#pragma once
/// @file error.hpp
/// @brief The one exception type smokescan throws for bad input: its message is the one-line
/// error the CLI prints ("FILE[:LINE]: problem").
#include <stdexcept>
#include <string>

namespace smokescan {

/// @brief `text` made safe to print on one line: control bytes, bytes that are not valid UTF-8 and
/// line breaks become `\xNN` (backslash itself stays), and C1 controls, bidirectional overrides
/// and line separators `\uXXXX`, so a message quoting a binary input is still one readable line
/// that shows what it quotes.
/// @param max_bytes longer texts are cut there and end in "…"
std::string printable(const std::string& text, size_t max_bytes = 400);
/// @brief The whole of `text` made safe as printable() makes it, never cut (a name a report or
/// JSON file records: valid UTF-8 on one line).
std::string printableWhole(const std::string& text);

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& what) : std::runtime_error(printable(what, 2000)) {}
    /// @param where file (and optionally ":line" or key) the problem is in
    Error(const std::string& where, const std::string& problem)
        : std::runtime_error(printable(where.empty() ? problem : where + ": " + problem, 2000))
    {
    }
};

}  // namespace smokescan
