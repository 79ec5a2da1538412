// A 3D lidar's recorded frames replayed and tallied (pipeline/lidar_frames.hpp).
#include "smokescan/pipeline/lidar_frames.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <optional>

#include "smokescan/bag/bag_input.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/lidar/frame_index.hpp"
#include "smokescan/lidar/lidar_spec.hpp"
#include "smokescan/lidar/point_cloud_io.hpp"
#include "smokescan/scene/scene_io.hpp"

namespace smokescan {
namespace {

/// How far a frame's recorded start pose may lie from the scene's: beyond, the replay fires other
/// beams than the recorder did (a 5 cm error already shows as channel biases; the report gives it).
constexpr double kMaxPoseOff_m = 0.1, kMaxPoseOff_deg = 1;
/// The largest share of the replay's certain beams that may go unanswered before the frames are
/// refused as not this run's.
constexpr double kMaxMissedShare = 0.4;

/// The frames' listing against the sensor, before any work: every file there, each frame as long
/// as the sensor's at its rate (another rate or column count is another span), none overlapping.
void checkListing(const std::vector<FrameIndexEntry>& frames, size_t min_frames, const std::string& dir,
                  const LidarScanner& scanner, const std::string& sensor, bool bag, const Scene& scene)
{
    const std::string index = bag ? dir : dir + "/frames.csv";
    if (frames.size() < min_frames)
        throw Error(index,
                    "holds " + std::to_string(frames.size()) + (frames.size() == 1 ? " frame" : " frames") +
                        (min_frames == 2 ? ": the diagnosis needs two at least (one to search, one held out)"
                                         : ": no frame to read"));
    const double span = scanner.pattern().back().time_s;
    for (size_t k = 0; k < frames.size(); ++k) {
        const FrameIndexEntry& e = frames[k];
        // Within the scene's time: a recording's wall-clock stamps (seconds since 1970) would
        // replay a scene nobody described there and name causes for what is only the clock.
        if (e.start_s < scene.t_start_s - kFrameTimeTolerance_s || e.end_s > scene.t_end_s + kFrameTimeTolerance_s)
            throw Error(bag ? e.file : index + ", frame " + std::to_string(e.frame) + " (" + e.file + ")",
                        fmt("runs from %.9g to %.9g s, outside the scene's time, %g to %g s (a recording's "
                            "stamps must be brought to the scene's clock: docs/bags.md)",
                            e.start_s, e.end_s, scene.t_start_s, scene.t_end_s));
        if (bag) {  // a frame a message, from its stamp: the sensor's span, none overlapping
            if (k > 0 && e.start_s < frames[k - 1].end_s - kFrameTimeTolerance_s)
                throw Error(e.file,
                            fmt("starts %.6g s after the previous frame, before it ends (the %s's frame spans %.6g "
                                "s: another rate or column count?)",
                                e.start_s - frames[k - 1].start_s, sensor.c_str(), span));
            continue;
        }
        const std::string where = index + ", frame " + std::to_string(e.frame) + " (" + e.file + ")";
        std::error_code ec;  // a name too long for the file system is a missing file, not a throw
        if (!std::filesystem::is_regular_file(dir + "/" + e.file, ec))
            throw Error(where, "its file is missing or not a file" + (ec ? " (" + ec.message() + ")" : std::string()));
        if (std::abs((e.end_s - e.start_s) - span) > kFrameTimeTolerance_s)
            throw Error(where,
                        fmt("spans %.6g s where the %s's frame spans %.6g s (another rate or column count?)",
                            e.end_s - e.start_s, sensor.c_str(), span));
        if (k > 0 && e.start_s < frames[k - 1].end_s) throw Error(where, "starts before the previous frame ends");
    }
}

/// One frame's file against its listing and the scene: the fields that tell a point's beam, the
/// file's own start time, the recorded start pose against the scene's.
/// A recorded pose's distance from the scene's: position [m] and angle [deg].
std::pair<double, double> poseOffset(const Pose& scene_pose, const Pose& recorded)
{
    return {(scene_pose.t - recorded.t).norm(),
            Eigen::AngleAxisd(scene_pose.R.transpose() * recorded.R).angle() * 180 / M_PI};
}

/// @return the recorded start pose's offset from the scene's (poseOffset); NaN without one
std::pair<double, double> checkFrame(const PointCloudFile& pc, const FrameIndexEntry& e, const Pose& scene_pose,
                                     const std::string& path, bool recorded_pose, bool need_fields)
{
    const auto has = [&](const char* a, const char* b) {
        return std::any_of(pc.fields.begin(), pc.fields.end(), [&](const std::string& f) { return f == a || f == b; });
    };
    for (const char* field : {"ring", "time"})
        if (need_fields && !has(field, field[0] == 't' ? "t" : field))
            throw Error(path,
                        std::string("has no ") + field +
                            " field: the diagnosis tells a point's beam by its ring and firing time");
    if (std::isfinite(pc.start_s) && std::abs(pc.start_s - e.start_s) > kFrameTimeTolerance_s)
        throw Error(path, fmt("starts at %.9g s by its header, at %.9g s by frames.csv", pc.start_s, e.start_s));
    if (!recorded_pose) return {NAN, NAN};
    const auto [off_m, off_deg] = poseOffset(scene_pose, e.start_pose);
    if (off_m > kMaxPoseOff_m || off_deg > kMaxPoseOff_deg)
        throw Error(path,
                    fmt("its recorded start pose is %.3g m and %.3g deg from the scene's (at most %g m and %g "
                        "deg): the replay would not fire the beams the recorder fired",
                        off_m, off_deg, kMaxPoseOff_m, kMaxPoseOff_deg));
    return {off_m, off_deg};
}

/// Refuses a frame whose first returns match no beam of the sensor in more than a tenth.
void checkMatched(long long unmatched, long long first_returns, const std::string& path, const std::string& sensor)
{
    if (first_returns >= 100 && 10 * unmatched > first_returns)
        throw Error(path,
                    std::to_string(unmatched) + " of " + std::to_string(first_returns) +
                        " points match no beam of the " + sensor +
                        " (by ring, firing time, direction and range): are these its frames, at its rate, "
                        "columns and numbering of rings?");
}

/// A frame is empty in effect (a recorder's dropped or cut frame, not the sensor's reading) when
/// its first returns number under this share of the beams the replay is sure of (at least 100
/// of them): no point at all, a point or two, or second returns alone.
constexpr double kEmptyFrameShare = 0.1;
constexpr long long kEmptyFrameSure = 100;

/// Whether a frame is empty in effect against its replay: `written` the first-return points the
/// recorder wrote (its first returns and a driver's "no return" points of return index 0: a frame
/// that writes every beam, as an organized cloud does, is a reading even when the sensor saw
/// nothing).
bool emptyInEffect(long long written, const std::vector<ExpectedBeam>& expected)
{
    if (written == 0) return true;
    long long sure = 0;
    for (const ExpectedBeam& x : expected) sure += x.clear;
    return sure >= kEmptyFrameSure && double(written) < kEmptyFrameShare * double(sure);
}

/// Refuses a listing of `frames` once more than kMaxMissedShare of them are empty in effect
/// (`empty` of the `seen` read so far).
void checkEmptyShare(size_t empty, size_t frames, const std::string& dir, size_t seen)
{
    if (double(empty) > kMaxMissedShare * double(frames))
        throw Error(
            dir,
            fmt("%zu of its %zu frames%s hold no point, or points for under a tenth of the beams the "
                "replay is sure of (at most %.0f %% of the frames may): a recorder that dropped or cut "
                "them, or frames of another sensor or topic?",
                empty, frames, seen < frames ? fmt(" (after %zu read)", seen).c_str() : "", 100 * kMaxMissedShare));
}

/// What the frames hold as a whole against what the diagnosis assumes: second returns exactly when
/// the mode is dual (`second_in` the first frame that holds one); most clear beams answered.
void checkWhole(const LidarTally& t, long long first, long long second, const std::string& second_in, ReturnMode mode,
                const std::string& dir)
{
    if (mode == ReturnMode::Dual && first >= 1000 && second == 0)
        throw Error("--returns", "dual, but the frames in " + dir + " hold no second return");
    if (mode != ReturnMode::Dual && second > 0)
        throw Error("--returns",
                    std::string(returnModeName(mode)) + ", but the frames in " + dir + " hold " +
                        std::to_string(second) + " second returns, the first in " + second_in + " (--returns dual?)");
    long long clear = 0, missed = 0;
    for (int k : {0, 1})
        for (size_t i = 0; i < t.pattern().size(); ++i) clear += t.fold(k).clear[i], missed += t.fold(k).missed[i];
    if (clear > 0 && double(missed) > kMaxMissedShare * double(clear))
        throw Error(dir,
                    fmt("%.0f %% of the beams the replay is sure of have no recorded return (at most %.0f %%): "
                        "empty frames, another column count or return mode, or another room?",
                        100.0 * double(missed) / double(clear), 100 * kMaxMissedShare));
}

}  // namespace

bool isLidarFramesBag(const std::string& points)
{
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::is_directory(points, ec))
        return !fs::exists(fs::path(points) / "frames.csv", ec) && fs::exists(fs::path(points) / "metadata.yaml", ec);
    return fs::is_regular_file(points, ec) && isBagPath(points);
}

namespace {

/// Refuses a folder without frames.csv that holds an .mcap (any case) but no metadata.yaml (a
/// bag's file copied alone into a folder), naming the files to give instead: how many, and the
/// first three by name (the folder's first 10,000 entries are looked at).
void noBagWithoutItsMetadata(const std::string& dir)
{
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::is_directory(dir, ec) || fs::exists(fs::path(dir) / "frames.csv", ec)) return;
    std::vector<std::string> mcaps;
    size_t looked = 0;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end && looked < 10000; it.increment(ec), ++looked) {
        std::string ext = it->path().extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        if (ext == ".mcap") mcaps.push_back(it->path().string());
    }
    if (mcaps.empty()) return;
    std::sort(mcaps.begin(), mcaps.end());
    const std::string what = "holds no frames.csv (a scan --points folder) and no metadata.yaml (a rosbag2 folder): ";
    if (mcaps.size() == 1) throw Error(dir, what + "give --points its file " + mcaps.front());
    std::string list;
    for (size_t k = 0; k < std::min<size_t>(3, mcaps.size()); ++k) list += (k ? ", " : "") + mcaps[k];
    throw Error(dir,
                what + "give --points one of its " + std::to_string(mcaps.size()) + " .mcap files (" + list +
                    (mcaps.size() > 3 ? ", …)" : ")"));
}

/// Thrown through the bag's reader to stop it at once (not an Error, which the reader may keep
/// until the bag's end to name the right one).
struct StopReading {};

/// Each PointCloud2 of the bag's topic to `each`, in order; a cancel asked of `control` stops the
/// reading at once and throws Cancelled.
/// Returns the topic read.
std::string eachBagCloud(const std::string& bag, const std::string& topic, const RunControl& control,
                         const std::function<void(const PointCloud2Msg&, double, const std::string&)>& each)
{
    std::optional<Cancelled> cancelled;
    try {
        return readBagPointClouds(bag, topic, [&](const PointCloud2Msg& m, double start_s, const std::string& what) {
            try {
                checkCancel(control);
                each(m, start_s, what);
            } catch (const Cancelled& c) {
                cancelled = c;
                throw StopReading{};
            }
        });
    } catch (const StopReading&) {
        throw *cancelled;
    }
}

/// A bag's frames as a listing: one a PointCloud2 message, starting at its stamp and spanning the
/// sensor's frame (set by the caller); `file` names the message. `read` is set to the topic read.
/// More than `most` frames are refused as they are listed, not after the bag's last.
std::vector<FrameIndexEntry> bagListing(const std::string& bag, const std::string& topic, const RunControl& control,
                                        int64_t most, std::string& read)
{
    std::vector<FrameIndexEntry> frames;
    // The stamps alone: the points are read in the tally's pass.
    read = eachBagCloud(bag, topic, control, [&](const PointCloud2Msg&, double start_s, const std::string& what) {
        if (int64_t(frames.size()) >= limits::kFrames)
            throw Error(what, "is past the " + std::to_string(limits::kFrames) + " frames a run may hold");
        if (int64_t(frames.size()) >= most)
            throw Error("--points",
                        bag + " holds more than " + std::to_string(most) + " frames: their readings would pass the " +
                            std::to_string(limits::kKeptReadings) + " a run keeps (fewer frames)");
        FrameIndexEntry e;
        e.frame = frames.size();
        e.file = what;
        e.start_s = e.end_s = start_s;
        frames.push_back(e);
    });
    return frames;
}

}  // namespace

void tallyLidarFrames(const LidarFramesConfig& cfg, size_t min_frames, const RunControl& control,
                      const std::function<void(const TalliedFrames&)>& use)
{
    if (cfg.points.empty()) throw Error("--points", "names no folder");
    const bool bag = isLidarFramesBag(cfg.points);
    std::error_code ec;
    if (!bag && !std::filesystem::is_directory(cfg.points, ec))
        throw Error("--points", cfg.points + " is not a folder of frames, a ROS 2 bag or a ROS 1 bag");
    if (!bag) noBagWithoutItsMetadata(cfg.points);
    if (!bag && !cfg.topic.empty())
        throw Error("--topic", "names a bag's topic, and " + cfg.points + " is a folder of frames (frames.csv)");
    const Scene scene = loadScene(cfg.scene);
    if (cfg.on_scene) cfg.on_scene(scene);
    // The run gives the scanner, its mount and mode (its options checked before the frames are
    // listed); each frame is replayed at its own start (checkListing names a frame outside the
    // scene's time).
    LidarRunConfig sc = cfg.sensor;
    sc.from_s = sc.to_s = NAN;
    const LidarRun run(scene, sc);
    const LidarScanner& scanner = run.scanner();
    // A bag of more frames than a run keeps the readings of is refused as it is listed.
    const int64_t most =
        std::min(limits::kFrames, limits::kKeptReadings / int64_t(std::max<size_t>(1, scanner.pattern().size())));
    std::string topic;
    std::vector<FrameIndexEntry> frames =
        bag ? bagListing(cfg.points, cfg.topic, control, most, topic) : readFrameIndex(cfg.points);
    const std::string sensor = run.spec().name;
    if (bag)
        for (FrameIndexEntry& e : frames) e.end_s = e.start_s + scanner.pattern().back().time_s;
    checkListing(frames, min_frames, cfg.points, scanner, sensor, bag, scene);
    // What lidar.toml will name, checked before any work: the base as the file system resolves
    // it, a text TOML and JSON can hold.
    std::string base = run.spec().base.empty() ? cfg.sensor.sensor : run.spec().base;
    if (isLidarPresetFile(base)) base = std::filesystem::weakly_canonical(std::filesystem::absolute(base)).string();
    if (printableWhole(base) != base)
        throw Error("--sensor",
                    "the preset's path " + base +
                        " holds bytes lidar.toml cannot name (control characters or bytes that are not UTF-8)");
    if (cfg.on_run) cfg.on_run(run);
    const double readings = double(frames.size()) * double(scanner.pattern().size());
    if (readings > double(limits::kKeptReadings))
        throw Error("--points",
                    limits::count(double(frames.size())) + " frames of " +
                        limits::count(double(scanner.pattern().size())) + " beams would keep " +
                        limits::count(readings) + " readings (at most " + std::to_string(limits::kKeptReadings) +
                        "; fewer frames)");
    LidarTally tally(scanner.pattern(), run.spec().channels(), returnTolerance_m(run.spec()), run.spec().range_max_m);
    tally.keepIntensities(cfg.intensities);
    double mismatch_m = 0, mismatch_deg = 0;
    std::vector<std::pair<double, std::vector<LidarPoint>>> recorded;
    long long first = 0, second = 0;
    std::string second_in;  // the first frame holding a second return
    size_t empty = 0, kept = 0;
    // Frame k of the listing, its points read from `path`. A frame empty in effect (a recorder's
    // dropped or cut frame) is left out, and one of no point not even replayed: their share of the
    // listing is checked as they come. The frames kept alternate between the folds.
    auto tallyFrame = [&](size_t k, PointCloudFile&& pc, const std::string& path) {
        checkCancel(control);
        const FrameIndexEntry& e = frames[k];
        // A message of no point at all needs no fields (a recorder may write it bare).
        const bool nothing = pc.points.empty() && pc.skipped == 0;
        const auto [off_m, off_deg] =
            checkFrame(pc, e, scene.sensorAt(run.mount(), e.start_s).pose, path, !bag, !nothing);
        if (cfg.intensities && !nothing &&
            std::find(pc.fields.begin(), pc.fields.end(), "intensity") == pc.fields.end())
            throw Error(path, "has no intensity field: the fit reads each point's intensity");
        auto leaveOut = [&] {
            // Refused as soon as the listing's share is passed, not after the frames left.
            checkEmptyShare(++empty, frames.size(), cfg.points, k + 1);
            reportProgress(control, (long long)k + 1, (long long)frames.size());
        };
        if (nothing) return leaveOut();
        long long frame_first = 0, frame_second = 0;
        for (const LidarPoint& p : pc.points) {
            // A lidar keeps two returns at most (the first kept and a second): a third is not a
            // return this diagnosis reads, and dropping it would be silent.
            if (p.return_index > 1)
                throw Error(path,
                            "holds a point of return index " + std::to_string(int(p.return_index)) +
                                " (0 the first kept return, 1 the second: a lidar keeps two at most)");
            (p.return_index == 0 ? frame_first : frame_second) += 1;
        }
        second += frame_second;  // every frame's: a mode without them refuses any (checkWhole)
        if (frame_second > 0 && second_in.empty()) second_in = path;
        const std::vector<ExpectedBeam> expected = scanner.expected(e.start_s, cfg.intensities);
        if (emptyInEffect(frame_first + (long long)pc.skipped_first, expected)) return leaveOut();
        first += frame_first;
        const long long before = tally.unmatched();
        tally.add(expected, pc.points, int(kept++ % 2));
        if (cfg.keep_points) recorded.emplace_back(e.start_s, std::move(pc.points));
        checkMatched(tally.unmatched() - before, frame_first, path, sensor);
        mismatch_m = std::max(mismatch_m, off_m);
        mismatch_deg = std::max(mismatch_deg, off_deg);
        reportProgress(control, (long long)k + 1, (long long)frames.size());
    };
    if (bag) {
        size_t k = 0;
        eachBagCloud(cfg.points, cfg.topic, control,
                     [&](const PointCloud2Msg& m, double start_s, const std::string& what) {
                         if (k >= frames.size() || frames[k].start_s != start_s)
                             throw Error(what, "is not the frame the first reading found there (did the bag change?)");
                         tallyFrame(k++, pointCloudFileOf(m, what), what);
                     });
        if (k != frames.size()) throw Error(cfg.points, "lost frames between two readings (did the bag change?)");
        mismatch_m = mismatch_deg = NAN;  // a bag's frames carry no pose
    } else {
        for (size_t k = 0; k < frames.size(); ++k) {
            const std::string path = cfg.points + "/" + frames[k].file;
            tallyFrame(k, readPointCloud(path), path);
        }
    }
    if (kept < min_frames)
        throw Error(cfg.points,
                    fmt("holds %zu frames that are not empty (points for a tenth of the beams the replay "
                        "is sure of): the diagnosis needs %zu",
                        kept, min_frames));
    checkWhole(tally, first, second, second_in, run.mode(), cfg.points);
    use(TalliedFrames{scene, run, tally, base, mismatch_m, mismatch_deg, std::move(recorded), topic, empty});
}

}  // namespace smokescan
