// Option checks shared by the subcommands (commands.hpp).
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>

#include "commands.hpp"
#include "smokescan/bag/bag_input.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/io/run_files.hpp"
#include "smokescan/pipeline/lidar_frames.hpp"
#include "smokescan/scene/scene_io.hpp"

namespace smokescan::cli {
namespace {

/// The option's text as a finite number, or why not.
std::string parseFinite(const std::string& text, double& v)
{
    char* end = nullptr;
    errno = 0;
    v = std::strtod(text.c_str(), &end);
    if (text.empty() || end == text.c_str() || *end) return "'" + text + "' is not a number";
    if (!std::isfinite(v) || errno == ERANGE) return "'" + text + "' is not a finite number";
    return "";
}

CLI::Validator numberRule(const char* name, bool (*ok)(double), const char* rule)
{
    return CLI::Validator(
        [ok, rule](std::string& text) {
            double v = 0;
            const std::string why = parseFinite(text, v);
            if (!why.empty()) return why;
            return ok(v) ? std::string() : "'" + text + "' " + rule;
        },
        name);
}

}  // namespace

const CLI::Validator& finite()
{
    static const CLI::Validator v = numberRule(
        "FINITE", [](double) { return true; }, "");
    return v;
}

const CLI::Validator& positive()
{
    static const CLI::Validator v = numberRule(
        "POSITIVE", [](double x) { return x > 0; }, "must be > 0");
    return v;
}

const CLI::Validator& nonEmpty()
{
    static const CLI::Validator v(
        [](const std::string& text) { return text.empty() ? std::string("must not be empty") : std::string(); },
        "NONEMPTY");
    return v;
}

const CLI::Validator& nonnegative()
{
    static const CLI::Validator v = numberRule(
        "NONNEGATIVE", [](double x) { return x >= 0; }, "must be >= 0");
    return v;
}

CLI::Validator range(double lo, double hi)
{
    char name[64];
    std::snprintf(name, sizeof name, "NUMBER in [%g, %g]", lo, hi);
    return CLI::Validator(
        [lo, hi](std::string& text) {
            double v = 0;
            const std::string why = parseFinite(text, v);
            if (!why.empty()) return why;
            if (v >= lo && v <= hi) return std::string();
            char buf[96];
            std::snprintf(buf, sizeof buf, "' is outside [%g, %g]", lo, hi);
            return "'" + text + buf;
        },
        name);
}

const CLI::Validator& seedRule()
{
    static const CLI::Validator v(
        [](std::string& text) {
            char* end = nullptr;
            errno = 0;
            const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
            const unsigned long long v = digits ? std::strtoull(text.c_str(), &end, 10) : 0;
            if (!digits || errno == ERANGE)
                return "'" + text + "' is not a seed (a whole number from 0 to 18446744073709551615)";
            text = std::to_string(v);  // decimal as written: CLI11 would read "010" as octal
            return std::string();
        },
        "SEED");
    return v;
}

CLI::Validator intRange(long long lo, long long hi)
{
    return CLI::Validator(
        [lo, hi](std::string& text) {
            char* end = nullptr;
            errno = 0;
            const long long v = std::strtoll(text.c_str(), &end, 10);
            if (text.empty() || *end || errno == ERANGE) return "'" + text + "' is not an integer";
            if (v < lo || v > hi)
                return "'" + text + "' is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
            return std::string();
        },
        "INT in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

SensorModel sensorModelOption(const std::string& option, const std::string& value)
{
    if (const auto m = parseSensorModel(value)) return *m;
    throw Error(option, "unknown sensor model '" + value + "' (paper, physical)");
}

void say(const char* format, ...)
{
    va_list args, again;
    va_start(args, format);
    va_copy(again, args);
    const int n = std::vsnprintf(nullptr, 0, format, args);
    va_end(args);
    std::string text(size_t(std::max(n, 0)) + 1, '\0');
    std::vsnprintf(text.data(), text.size(), format, again);
    va_end(again);
    text.resize(size_t(std::max(n, 0)));
    for (size_t start = 0; start < text.size();) {
        const size_t end = std::min(text.find('\n', start), text.size());
        std::fputs(printable(text.substr(start, end - start), size_t(1) << 20).c_str(), stdout);
        if (end < text.size()) std::fputc('\n', stdout);
        start = end + 1;
    }
}

void recordSceneInputs(RunFiles& files, const std::string& path, const Scene& scene)
{
    files.input(path, "the scene");
    for (const std::string& f : sceneFiles(scene)) files.input(f, "a file the scene reads");
}

void addOmniClassOptions(CLI::App* c, OmniFitConfig& omni, std::set<std::string>& given)
{
    const auto option = [&](const char* name, double& v, const char* help) {
        c->add_option(name, v, help)->capture_default_str()->check(finite())->each([&given, name](const std::string&) {
            given.insert(name);
        });
    };
    option("--max-range", omni.max_range_m, "omnicam: the rangefinder's maximum range [m]");
    option("--floor-z", omni.floor_z_m, "omnicam: the floor's height [m]");
    option("--tolerance", omni.tolerance_m, "omnicam: a reading further than this from its truth failed [m]");
}

void addScansOptions(CLI::App* c, std::string& laser, std::string& bag, std::string& topic, const char* laser_help)
{
    c->add_option("--laser", laser, laser_help)->check(nonEmpty());
    c->add_option(
         "--bag", bag,
         "Or a bag: a rosbag2 folder, .mcap or ROS 1 .bag file whose sensor_msgs/LaserScan topic holds the scans "
         "(docs/bags.md)")
        ->check(nonEmpty());
    c->add_option("--topic", topic,
                  "The bag's LaserScan topic (default: its only one); with --points, a bag's PointCloud2 topic")
        ->check(nonEmpty());
}

CLI::Option* addSaturationOptions(CLI::App* c, std::string& saturation, std::string& image_topic,
                                  std::vector<std::string>& rects, std::vector<std::string>& polygons,
                                  const std::string& help)
{
    CLI::Option* o = c->add_option(
        "--saturation", saturation,
        help +
            "; or a bag (ROS 2 or ROS 1) whose camera frames are measured (--image-topic, --rect/--polygon; docs/bags.md)");
    c->add_option("--image-topic", image_topic, "The --saturation bag's Image topic (default: its only one)")
        ->check(nonEmpty());
    c->add_option("--rect", rects, "The target in the bag's frames: NAME=x,y,width,height in pixels (repeatable)");
    c->add_option("--polygon", polygons, "The target in the bag's frames: NAME=x1,y1,x2,y2,x3,y3,... (repeatable)");
    return o;
}

bool lidarRun(const std::vector<std::string>& given, const std::set<std::string>& lidar_options, const char* run)
{
    static const std::set<std::string> kLidarOnly = {"--points", "--returns", "--columns", "--rate"};
    const bool lidar = std::find(given.begin(), given.end(), "--points") != given.end();
    for (const std::string& o : given) {
        if (lidar && !lidar_options.count(o))
            throw Error(o, fmt("is not an option of a 3D lidar's %s (--points)", run));
        if (!lidar && kLidarOnly.count(o)) throw Error(o, "is a 3D lidar's option (with --points)");
    }
    return lidar;
}

void bagInputs(RunFiles& files, const std::string& bag, const std::string& option)
{
    if (bag.empty()) return;
    for (const std::string& f : bagInputFiles(bag)) files.input(f, option);
}

void lidarFramesInputs(RunFiles& files, const std::string& points)
{
    if (isLidarFramesBag(points)) return bagInputs(files, points, "--points");
    files.input(points + "/frames.csv", "--points");
}

void outsideLidarFrames(const std::string& path, const char* option, const std::string& points)
{
    namespace fs = std::filesystem;
    std::error_code ec;
    // The folder no output may lie in: `points` itself, or the rosbag2 folder holding an .mcap
    // (where the file is, through any symbolic link to it).
    std::string folder = points;
    const fs::path parent = fs::weakly_canonical(fs::absolute(points, ec), ec).parent_path();
    if (fs::is_regular_file(points, ec) && fs::exists(parent / "metadata.yaml", ec)) folder = parent.string();
    const fs::path inside =
        fs::weakly_canonical(fs::absolute(path), ec).lexically_relative(fs::weakly_canonical(fs::absolute(folder), ec));
    if (!ec && !inside.empty() && *inside.begin() != "..")
        throw Error(option, path + " lies in the frames' folder " + folder + " (an input)");
}

void saturationInputs(RunFiles& files, const std::string& saturation)
{
    if (saturation.empty() || !isBagPath(saturation)) return files.input(saturation, "--saturation");
    bagInputs(files, saturation, "--saturation");
}

}  // namespace smokescan::cli
