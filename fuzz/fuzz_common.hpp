#pragma once
// Shared by the fuzz targets: each feeds the fuzzer's bytes to one reader. A reader may refuse
// any input with smokescan::Error (a one-line message); any other exception, a crash, a
// sanitizer report, a hang or a memory blow-up is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "smokescan/core/error.hpp"

template <class F>
int fuzzReader(const uint8_t* data, size_t size, F&& read)
{
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        read(text);
    } catch (const smokescan::Error& e) {
        const std::string m = e.what();
        if (m.find('\n') != std::string::npos) __builtin_trap();  // an error is one line
    }
    return 0;
}
