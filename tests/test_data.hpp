#pragma once
// Where tests find their data: the project's own grids in volumes/ (made by
// volumes/make_test_grids.sh, committed), and third-party files that may not be redistributed,
// found through SMOKESCAN_EXTERNAL_VDB (a folder holding teapot_cloud.vdb and
// smoke_dense_double.vdb; .ci/run points it at ../shared/data/vdb when that exists). A test that
// needs an external file skips, saying why, when it is not there.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace smokescan::test {

/// A grid of the project's: <source>/volumes/NAME.
inline std::string projectVolume(const std::string& name)
{
    return std::string(SMOKESCAN_SOURCE_DIR) + "/volumes/" + name;
}

/// The third-party file NAME in $SMOKESCAN_EXTERNAL_VDB, or "" when it is not there.
inline std::string externalVdb(const std::string& name)
{
    const char* dir = std::getenv("SMOKESCAN_EXTERNAL_VDB");
    if (!dir || !*dir) return "";
    const std::string p = std::string(dir) + "/" + name;
    return std::filesystem::is_regular_file(p) ? p : "";
}

}  // namespace smokescan::test

/// Declares `var` as the path of external file `name`, or skips the test with the reason.
#define SMOKESCAN_EXTERNAL_VDB_OR_SKIP(var, name)                                                    \
    const std::string var = ::smokescan::test::externalVdb(name);                                    \
    if (var.empty())                                                                                 \
    GTEST_SKIP() << name                                                                             \
                 << " is a third-party file not shipped with smokescan: set SMOKESCAN_EXTERNAL_VDB " \
                    "to the folder holding it to run this test"
