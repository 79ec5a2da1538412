#pragma once
/// @file version.hpp
/// @brief The library's version (the project version in CMakeLists.txt).

namespace smokescan {

/// @brief "MAJOR.MINOR.PATCH" of the library this program links.
const char* version();

}  // namespace smokescan
