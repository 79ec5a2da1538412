// The module layers (docs/architecture.md): every file includes only its own module and the
// modules below it, so a cycle cannot form, and never reaches into another module's folder by a
// relative path (the build gives each module only its own folder; a header shared inside the
// project is an internal module's, seen by those that link it). The order is the one
// CMakeLists.txt links in.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <string>

#include "scratch.hpp"

namespace fs = std::filesystem;

namespace {

/// Rank of each module: a module may include those of lower rank. sensors and render share a
/// rank: neither may include the other.
const std::map<std::string, int> kRank = {
    {"core", 0},    {"io", 1},     {"toml", 1},      {"solve", 1},     {"media", 2}, {"sensor_config", 3}, {"scene", 4},
    {"sensors", 5}, {"render", 5}, {"plot", 6},      {"lidar", 6},     {"bag", 7},   {"camera", 7},        {"calib", 8},
    {"omni", 8},    {"fit", 9},    {"diagnose", 10}, {"pipeline", 11}, {"cli", 12}};

struct Violation {
    std::string file, line;
};

/// Every include in root/src and root/include/smokescan that reaches up the layers, or out of its
/// module's folder by a relative path.
std::vector<Violation> violations(const fs::path& root)
{
    const std::regex inc(R"re(^\s*#\s*include\s*["<](?:(?:\.\./)+|smokescan/)?([a-z_0-9]+)/([a-z_0-9]+)\.hpp[">])re");
    const std::regex relative(R"re(^\s*#\s*include\s*"((?:\.\./)+)[^"]*")re");
    std::vector<Violation> out;
    for (const fs::path base : {root / "src", root / "include" / "smokescan"})
        if (fs::exists(base))
            for (const auto& e : fs::recursive_directory_iterator(base)) {
                if (!e.is_regular_file() || !fs::exists(base)) continue;
                const fs::path rel = fs::relative(e.path(), base);
                const std::string folder = rel.begin()->string();
                if (!kRank.count(folder)) {  // a new module must be given its layer here
                    if (rel.has_parent_path())
                        out.push_back({e.path().string(), "(folder '" + folder + "' has no layer)"});
                    continue;
                }
                const std::string self = folder;
                // How deep below its module's folder the file lies: "../" more often leaves it.
                const long depth = long(std::distance(rel.begin(), rel.end())) - 2;
                std::ifstream in(e.path());
                for (std::string line; std::getline(in, line);) {
                    std::smatch m;
                    if (std::regex_search(line, m, relative) && long(m[1].length() / 3) > depth) {
                        out.push_back({e.path().string(), line + "   (" + self + " reaches out of its folder)"});
                        continue;
                    }
                    if (!std::regex_search(line, m, inc) || !kRank.count(m[1].str())) continue;
                    const std::string used = m[1].str();
                    if (used != self && kRank.at(used) >= kRank.at(self))
                        out.push_back({e.path().string(), line + "   (" + self + " includes " + used + ")"});
                }
            }
    return out;
}

}  // namespace

TEST(Architecture, EveryModuleIncludesOnlyModulesBelowIt)
{
    for (const auto& v : violations(SMOKESCAN_SOURCE_DIR)) ADD_FAILURE() << v.file << ": " << v.line;
}

TEST(Architecture, TheCheckSeesAnUpwardIncludeAndAReachIntoAnotherModule)
{
    // A scratch tree: a beam model including the fit, the renderer reaching into the sensors'
    // folder, a sensor model two folders down reaching into the fit's, and a folder without a
    // layer are refused; the scene including what a sensor is (its config) and the media, and a
    // sensor model including its own module's header one folder up, are not.
    const fs::path root = smokescan::test::scratch("layers");
    fs::create_directories(root / "src" / "sensors" / "urg04lx");
    fs::create_directories(root / "src" / "render");
    fs::create_directories(root / "src" / "scene");
    fs::create_directories(root / "src" / "newmodule");
    std::ofstream(root / "src" / "sensors" / "model.cpp") << "#include \"smokescan/fit/sensor_fit.hpp\"\n";
    std::ofstream(root / "src" / "render" / "x.cpp") << "#include \"../sensors/beam_models.hpp\"\n";
    std::ofstream(root / "src" / "sensors" / "urg04lx" / "m.cpp") << "#include \"../../fit/x.hpp\"\n";
    std::ofstream(root / "src" / "sensors" / "urg04lx" / "ok.cpp") << "#include \"../beam_models.hpp\"\n";
    std::ofstream(root / "src" / "scene" / "z.cpp") << "#include \"../media/grid_walk.hpp\"\n";  // down, but private
    std::ofstream(root / "src" / "newmodule" / "n.cpp") << "\n";
    std::ofstream(root / "src" / "scene" / "y.cpp") << "#include \"smokescan/sensor_config/sensor_config.hpp\"\n"
                                                    << "#include \"smokescan/media/smoke.hpp\"\n";
    const auto v = violations(root);
    ASSERT_EQ(v.size(), 5u);  // the fit from a sensor model, three reaches out, a folder without a layer
    int reaches = 0;
    for (const auto& x : v) {
        EXPECT_EQ(x.file.find("y.cpp"), std::string::npos) << x.line;
        EXPECT_EQ(x.file.find("ok.cpp"), std::string::npos) << x.line;
        reaches += x.line.find("reaches out of its folder") != std::string::npos;
    }
    EXPECT_EQ(reaches, 3);  // z.cpp's include goes down the layers: only the folder rule refuses it
}
