#pragma once
// The CLI's subcommands: each registers its options on the app and runs when chosen.
#include <CLI/CLI.hpp>

#include <filesystem>
#include <functional>
#include <string>

#include "smokescan/core/error.hpp"

namespace smokescan::cli {

using Runner = std::function<int()>;

/// Fails before any work when an output's folder does not exist (writes would fail at the end).
inline void requireOutputFolder(const std::string& path)
{
    if (path.empty()) return;
    const auto dir = std::filesystem::path(path).parent_path();
    if (!dir.empty() && !std::filesystem::is_directory(dir)) throw Error(path, "cannot write (no such directory)");
}

void addScan(CLI::App& app, Runner& run);
void addVolume(CLI::App& app, Runner& run);
void addScene(CLI::App& app, Runner& run);
void addRender(CLI::App& app, Runner& run);
void addCalibration(CLI::App& app, Runner& run);
void addFit(CLI::App& app, Runner& run);
void addFitPlume(CLI::App& app, Runner& run);

}  // namespace smokescan::cli
