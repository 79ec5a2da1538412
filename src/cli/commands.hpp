#pragma once
// The CLI's subcommands: each registers its options on the app and runs when chosen.
#include <CLI/CLI.hpp>

#include "smokescan/sensors/sensor_kind.hpp"

#include <functional>
#include <string>

#include "smokescan/core/error.hpp"

namespace smokescan::cli {

using Runner = std::function<int()>;

/// Option checks: each names the rule it enforces; nan and inf fail every one of them.
/// A number of any sign, finite.
const CLI::Validator& finite();
/// A finite number > 0.
const CLI::Validator& positive();
/// A finite number >= 0.
const CLI::Validator& nonnegative();
/// An integer in [lo, hi].
CLI::Validator intRange(long long lo, long long hi);
/// The sensor model an option names ("paper", "physical"); Error(option, ...) otherwise.
SensorModel sensorModelOption(const std::string& option, const std::string& value);
/// The sensor type an option names ("urg04lx", "lms200"); Error(option, ...) otherwise.
SensorType sensorTypeOption(const std::string& option, const std::string& value);

void addScan(CLI::App& app, Runner& run);
void addVolume(CLI::App& app, Runner& run);
void addScene(CLI::App& app, Runner& run);
void addRender(CLI::App& app, Runner& run);
void addCalibration(CLI::App& app, Runner& run);
void addFit(CLI::App& app, Runner& run);
void addFitPlume(CLI::App& app, Runner& run);

}  // namespace smokescan::cli
