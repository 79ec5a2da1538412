#pragma once
// Running the CLI from tests: its exit status, stdout and stderr; scratch files; and the check
// every bad input must pass (one line, exit != 0, no output, no temporaries left).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "scratch.hpp"

namespace smokescan::test {
namespace fs = std::filesystem;
struct CliRun {
    int status;
    std::string out, err;
};

/// The scratch folder of the CLI tests.
inline fs::path dir()
{
    static const fs::path d = scratch("cli");
    return d;
}

inline std::string slurp(const fs::path& p)
{
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

inline CliRun cli(const std::string& args)
{
    const fs::path o = dir() / "stdout", e = dir() / "stderr";
    const std::string cmd = std::string(SMOKESCAN_CLI) + " " + args + " >" + o.string() + " 2>" + e.string();
    const int rc = std::system(cmd.c_str());
    return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, slurp(o), slurp(e)};
}

inline std::string file(const std::string& name, const std::string& text = "")
{
    const fs::path p = dir() / name;
    if (!text.empty()) std::ofstream(p) << text;
    return p.string();
}

/// Bad input: non-zero exit, exactly one line on stderr that contains `needle`, no output file.
inline void expectBad(const std::string& args, const std::string& needle, const std::string& out_file)
{
    const CliRun r = cli(args);
    EXPECT_NE(r.status, 0) << args;
    EXPECT_NE(r.err.find(needle), std::string::npos) << args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(out_file)) << out_file;
    for (const auto& e : fs::directory_iterator(dir()))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << "left a temporary " << e.path();
}

/// A small recorded run for the fit commands (scan's own laser log and camera saturation, bocas
/// 80–130 s at 2 Hz), made once per test process.
struct RecordedRun {
    std::string log, sat;
};
inline const RecordedRun& recordedRun()
{
    static const RecordedRun r = [] {
        RecordedRun x{file("run.log"), file("run_sat.csv")};
        const CliRun c =
            cli("scan bocas --from 80 --to 130 --rate 2 --quiet --out " + x.log + " --saturation-out " + x.sat);
        EXPECT_EQ(c.status, 0) << c.err;
        return x;
    }();
    return r;
}

}  // namespace smokescan::test
