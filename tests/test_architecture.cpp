// The module layers (docs/architecture.md): every file includes only its own module and the
// modules below it, so a cycle cannot form. The order is the one CMakeLists.txt links in.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>

#include "scratch.hpp"

namespace fs = std::filesystem;

namespace {

/// Rank of each module: a module may include those of lower rank. sensors and render share a
/// rank: neither may include the other.
const std::map<std::string, int> kRank = {
    {"core", 0}, {"io", 1},     {"media", 2}, {"sensor_config", 3}, {"scene", 4}, {"sensors", 5},   {"render", 5},
    {"plot", 6}, {"camera", 7}, {"calib", 8}, {"omni", 8},          {"fit", 9},   {"diagnose", 10}, {"cli", 11}};

/// The sensors module's lower layer: what a sensor is (CMakeLists.txt: sensor_config_names, and
/// the header-only extensions.hpp).
const std::set<std::string> kSensorConfig = {"sensor_kind",   "lrf",         "physical_params", "sensor_config",
                                             "sensor_tables", "sensor_file", "extensions"};

/// The module a folder name and file stem belong to.
std::string moduleOf(const std::string& folder, const std::string& stem)
{
    return folder == "sensors" && kSensorConfig.count(stem) ? "sensor_config" : folder;
}

struct Violation {
    std::string file, line;
};

/// Every include in root/src and root/include/smokescan that reaches up the layers.
std::vector<Violation> violations(const fs::path& root)
{
    const std::regex inc(R"re(^\s*#\s*include\s*["<](?:(?:\.\./)+|smokescan/)?([a-z_0-9]+)/([a-z_0-9]+)\.hpp[">])re");
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
                const std::string self = moduleOf(folder, e.path().stem().string());
                std::ifstream in(e.path());
                for (std::string line; std::getline(in, line);) {
                    std::smatch m;
                    if (!std::regex_search(line, m, inc) || !kRank.count(m[1].str())) continue;
                    const std::string used = moduleOf(m[1].str(), m[2].str());
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

TEST(Architecture, TheCheckSeesAnUpwardInclude)
{
    // A scratch tree: a beam model including the fit and the renderer including a sensor model
    // are refused; the scene including what a sensor is (its config) is not.
    const fs::path root = smokescan::test::scratch("layers");
    fs::create_directories(root / "src" / "sensors");
    fs::create_directories(root / "src" / "render");
    fs::create_directories(root / "src" / "scene");
    std::ofstream(root / "src" / "sensors" / "model.cpp") << "#include \"smokescan/fit/sensor_fit.hpp\"\n";
    std::ofstream(root / "src" / "render" / "x.cpp") << "#include \"../sensors/beam_models.hpp\"\n";
    fs::create_directories(root / "src" / "sensors" / "urg04lx");
    std::ofstream(root / "src" / "sensors" / "urg04lx" / "m.cpp") << "#include \"../../fit/x.hpp\"\n";
    fs::create_directories(root / "src" / "newmodule");
    std::ofstream(root / "src" / "newmodule" / "n.cpp") << "\n";
    std::ofstream(root / "src" / "scene" / "y.cpp") << "#include \"smokescan/sensors/sensor_config.hpp\"\n"
                                                    << "#include \"smokescan/media/smoke.hpp\"\n";
    const auto v = violations(root);
    ASSERT_EQ(v.size(), 4u);  // the fit from a sensor model, twice; the renderer; a folder without a layer
    for (const auto& x : v) EXPECT_EQ(x.file.find("y.cpp"), std::string::npos) << x.line;
}
