#pragma once
// The message of the smokescan::Error a call throws, for tests that check what a refusal says.
#include <functional>
#include <string>

#include "smokescan/core/error.hpp"

namespace smokescan::test {

/// @brief f's Error message, or "" when it throws none.
inline std::string errorOf(const std::function<void()>& f)
{
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace smokescan::test
