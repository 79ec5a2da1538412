#pragma once
// Scratch folders for tests: one root per test process (ctest runs each test in its own),
// removed when that process's tests end, so runs leave nothing behind in the temp folder.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace smokescan::test {

/// <temp>/smokescan_tests_<pid>: everything a test process writes goes below it.
inline const std::filesystem::path& scratchRoot()
{
    static const std::filesystem::path root =
        std::filesystem::temp_directory_path() / ("smokescan_tests_" + std::to_string(::getpid()));
    return root;
}

/// The folder <scratch root>/<name>, created if missing.
inline std::filesystem::path scratch(const std::string& name)
{
    const std::filesystem::path p = scratchRoot() / name;
    std::filesystem::create_directories(p);
    return p;
}

/// Removes the scratch root after the last test of the process.
class ScratchCleanup : public ::testing::Environment {
public:
    void TearDown() override
    {
        std::error_code ec;
        std::filesystem::remove_all(scratchRoot(), ec);
    }
};

inline ::testing::Environment* const kScratchCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

}  // namespace smokescan::test
