#pragma once
/// @file text_input.hpp
/// @brief Text inputs read whole, within bounds: a missing file, a folder, a file over
/// limits::kTextInputBytes (or a device or pipe that keeps giving bytes), or binary content
/// (a NUL byte) is a one-line error naming the file, before anything is parsed.
#include <string>
#include <vector>

#include "smokescan/core/limits.hpp"

namespace smokescan {

/// @param path the file to read (a regular file, FIFO or character device)
/// @param what what the file is, for the error ("laser log", "scene file")
/// @param max_bytes the largest text accepted
/// @throw Error naming `path` for each case above.
std::string readTextInput(const std::string& path, const std::string& what, size_t max_bytes = limits::kTextInputBytes);

/// @brief The same for any bytes (a binary file): with `text_only`, a NUL byte is refused as
/// readTextInput refuses it, as soon as it is read.
std::string readInputBytes(const std::string& path, const std::string& what, size_t max_bytes, bool text_only = false);

/// @brief One finite number, the whole of `text` ("2.5e-3").
/// @param where names it in the error (an option, "FILE:LINE")
/// @throw Error(where, "'text' is not a finite number") for an empty, partial or non-finite one.
double parseFiniteNumber(const std::string& text, const std::string& where);

/// @brief Comma-separated finite numbers ("0,0.001,2e-3").
/// @param what names the text in the error (an option, "FILE:LINE")
/// @throw Error(what, "'tok' is not a finite number") for an empty or bad item.
std::vector<double> parseNumberList(const std::string& text, const std::string& what);

}  // namespace smokescan
