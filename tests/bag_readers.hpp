#pragma once
// The independent bag readers of the bag tests (tests/js/read_bag.mjs under node, installed by
// scripts/setup_readers.sh into SMOKESCAN_READERS_DIR) and helpers for the JSON they print.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_run.hpp"

namespace smokescan::test {

/// The independent readers' folder, or empty (the test skips, or fails when CI requires them).
inline std::string readersDir()
{
    const char* env = std::getenv("SMOKESCAN_READERS_DIR");
    const std::string d = env && *env ? env : SMOKESCAN_READERS_DIR;
    if (std::system("node --version >/dev/null 2>&1") != 0) return "";
    return fs::exists(fs::path(d) / "node_modules" / "@mcap" / "core") ? d : "";
}

inline nlohmann::json readIndependently(const std::string& mcap)
{
    const fs::path out = dir() / "read_bag.json", err = dir() / "read_bag.err";
    const std::string cmd =
        "node " + readersDir() + "/read_bag.mjs " + mcap + " >" + out.string() + " 2>" + err.string();
    EXPECT_EQ(std::system(cmd.c_str()), 0) << slurp(err);
    return nlohmann::json::parse(slurp(out));
}

#define SMOKESCAN_NEED_READERS()                                                                                 \
    if (readersDir().empty()) {                                                                                  \
        if (std::getenv("SMOKESCAN_REQUIRE_READERS")) FAIL() << "the independent bag readers are not installed"; \
        GTEST_SKIP() << "node or the bag readers are missing (scripts/setup_readers.sh; SMOKESCAN_READERS_DIR)"; \
    }

/// A range as the JSON carries it: a number, or "NaN", "Infinity", "-Infinity".
inline double number(const nlohmann::json& v)
{
    return v.is_string() ? std::stod(v.get<std::string>()) : v.get<double>();
}

/// Bytes of a base64 text (how the reader prints a uint8[] field).
inline std::string base64(const std::string& in)
{
    static const std::string k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    int bits = 0;
    uint32_t value = 0;
    for (char c : in) {
        if (c == '=') break;
        value = ((value << 6) | uint32_t(k.find(c))) & 0xFFFFFFu;
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out.push_back(char((value >> bits) & 0xFF));
        }
    }
    return out;
}

}  // namespace smokescan::test
