#pragma once
// The CLI's subcommands: each registers its options on the app and runs when chosen.
#include <CLI/CLI.hpp>

#include <functional>

namespace smokescan::cli {

using Runner = std::function<int()>;

void addScan(CLI::App& app, Runner& run);
void addVolume(CLI::App& app, Runner& run);
void addScene(CLI::App& app, Runner& run);
void addRender(CLI::App& app, Runner& run);
void addCalibration(CLI::App& app, Runner& run);

}  // namespace smokescan::cli
