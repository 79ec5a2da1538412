#pragma once
// The CLI's subcommands: each registers its options on the app and runs when chosen.
#include <CLI/CLI.hpp>

#include <functional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "smokescan/core/error.hpp"
#include "smokescan/fit/omni_fit.hpp"
#include "smokescan/sensor_config/sensor_kind.hpp"

namespace smokescan {
class RunFiles;
struct Scene;
}  // namespace smokescan

namespace smokescan::cli {

using Runner = std::function<int()>;

/// Option checks: each names the rule it enforces; nan and inf fail every one of them.
/// A number of any sign, finite.
const CLI::Validator& finite();
/// A finite number > 0.
const CLI::Validator& positive();
/// A finite number >= 0.
const CLI::Validator& nonnegative();
/// A finite number in [lo, hi] (CLI::Range lets "nan" through: never use it).
CLI::Validator range(double lo, double hi);
/// An integer in [lo, hi].
CLI::Validator intRange(long long lo, long long hi);
/// A seed: a whole number from 0 to 2⁶⁴ − 1 written in decimal digits (no sign, no wrap-around;
/// leading zeros are decimal, not octal). A transform: add it with ->transform().
const CLI::Validator& seedRule();
/// A text that is not empty (a surface-name prefix: "" would make every surface the target).
const CLI::Validator& nonEmpty();
/// The sensor model an option names ("paper", "physical"); Error(option, ...) otherwise.
SensorModel sensorModelOption(const std::string& option, const std::string& value);
/// @brief The omnicam's options of `fit` and `diagnose` (--max-range, --floor-z, --tolerance)
/// into `omni`; `given` collects the names of those on the command line.
void addOmniClassOptions(CLI::App* c, OmniFitConfig& omni, std::set<std::string>& given);
/// @brief The recorded scans' options: --laser LOG, or --bag PATH with --topic NAME.
void addScansOptions(CLI::App* c, std::string& laser, std::string& bag, std::string& topic, const char* laser_help);
/// @brief --saturation (`help` says what a CSV holds) and the options that measure it on a bag's
/// frames: --image-topic, --rect, --polygon.
CLI::Option* addSaturationOptions(CLI::App* c, std::string& saturation, std::string& image_topic,
                                  std::vector<std::string>& rects, std::vector<std::string>& polygons,
                                  const std::string& help);
/// @brief Whether the run reads a 3D lidar's frames (--points among `given`, the options on the
/// command line); throws Error naming the first option that does not belong to the run it chose:
/// one outside `lidar_options` with --points, one of a 3D lidar's own (--points, --returns,
/// --columns, --rate) without. `run` names the run in the message ("fit", "diagnosis").
bool lidarRun(const std::vector<std::string>& given, const std::set<std::string>& lidar_options, const char* run);
/// @brief A bag's files as the run's inputs, which no output may replace: a folder's metadata.yaml
/// and the files it lists, or the file itself; nothing when `bag` is empty.
void bagInputs(RunFiles& files, const std::string& bag, const std::string& option);
/// @brief The inputs of a 3D lidar's recorded frames (--points), which no output may replace: a
/// frames folder's frames.csv, or a ROS 2 bag's files.
void lidarFramesInputs(RunFiles& files, const std::string& points);
/// @brief Refuses an output `path` (given as `option`) inside the recorded frames' folder, an
/// input: `points` itself, or the rosbag2 folder holding an .mcap file (its metadata.yaml beside it).
void outsideLidarFrames(const std::string& path, const char* option, const std::string& points);
/// @brief The --saturation input's files (a bag's metadata.yaml and the files it lists, or the CSV).
void saturationInputs(RunFiles& files, const std::string& saturation);

/// @brief An option whose value is one of a few names, stored as the enum it names; any other
/// value is a parse error listing the names ("--link: 'x' is not one of probit, logistic").
template <class E>
CLI::Option* addChoice(CLI::App* c, const std::string& name, E& target, std::vector<std::pair<std::string, E>> choices,
                       const std::string& description)
{
    std::string names;
    for (const auto& ch : choices) names += (names.empty() ? "" : ", ") + ch.first;
    auto* o = c->add_option_function<std::string>(
        name,
        [&target, choices](const std::string& v) {
            for (const auto& ch : choices)
                if (ch.first == v) target = ch.second;
        },
        description + " (" + names + ")");
    o->check(CLI::Validator(
        [choices, names](std::string& v) {
            for (const auto& ch : choices)
                if (ch.first == v) return std::string();
            return "'" + v + "' is not one of " + names;
        },
        "NAME"));
    return o;
}

/// @brief Records the scene (`path`, when it is a file) and every file it read (meshes, grids,
/// sensor files) as inputs of the run, so that no output replaces them.
void recordSceneInputs(RunFiles& files, const std::string& path, const Scene& scene);

/// @brief printf to standard output, each line made printable (control characters, C1 controls
/// and bidirectional overrides escaped, as in errors): what the program prints quotes the user's
/// file names, surface names and groups. Every line the CLI prints goes through it.
void say(const char* format, ...) __attribute__((format(printf, 1, 2)));

void addScan(CLI::App& app, Runner& run);
void addVolume(CLI::App& app, Runner& run);
void addScene(CLI::App& app, Runner& run);
void addRender(CLI::App& app, Runner& run);
void addCalibration(CLI::App& app, Runner& run);
void addFit(CLI::App& app, Runner& run);
void addFitPlume(CLI::App& app, Runner& run);
void addDiagnose(CLI::App& app, Runner& run);
void addOmnirange(CLI::App& app, Runner& run);

}  // namespace smokescan::cli
