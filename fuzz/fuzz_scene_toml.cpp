// Fuzzes the scene reader: TOML text to a Scene, with every grid it describes built. Files the
// scene names are looked up in an empty folder (the fuzzer's inputs stay in memory).
#include <filesystem>

#include "fuzz_common.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/scene/surfaces.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    static const std::string base = [] {
        const auto d = std::filesystem::temp_directory_path() / "smokescan_fuzz_scene_base";
        std::filesystem::create_directories(d);
        return d.string();
    }();
    return fuzzReader(data, size, [](const std::string& text) {
        const smokescan::Scene scene = smokescan::parseScene(text, "fuzz.toml", base);
        for (const auto& v : scene.volumes) (void)v.gridAt(0.0);
    });
}
