#pragma once
/// @file lidar_run.hpp
/// @brief A 3D lidar's frames over a span of a scene as one library call: what `smokescan scan
/// --sensor PRESET` does, without its files. LidarRunConfig in; the frames out, one by one to a
/// sink or kept, with progress and cancellation (pipeline/run_control.hpp).
///
/// | field   | default      | unit | meaning                                                          |
/// |---------|--------------|------|------------------------------------------------------------------|
/// | sensor  | "vlp16"      | –    | a preset's name (vlp16, hdl32e, os1-128) or a preset file (.toml) |
/// | returns | ""           | –    | first, last, strongest or dual; "" = strongest where offered, else the sensor's first mode |
/// | rate_hz | 0            | Hz   | frames a second; 0 = the preset's                                 |
/// | columns | 0            | –    | columns a turn (a spinning lidar); 0 = the preset's               |
/// | from_s  | NaN          | s    | the first frame's start; NaN = the scene's start (±inf refused)  |
/// | to_s    | NaN          | s    | frames start up to this time; NaN = from_s (one frame)            |
/// | seed    | 1            | –    | the receiver's noise; frames do not depend on the thread count    |
///
/// The lidar sits on the scene's default lidar mount (lidar/lidar_scanner.hpp). Errors name the
/// command line's options (--returns, --to, ...), which these fields are.
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "smokescan/lidar/lidar_scanner.hpp"
#include "smokescan/pipeline/run_control.hpp"

namespace smokescan {

/// How far a frame's times may stray from the sensor's and the scene's [s] (frames.csv keeps them
/// to 1e-9 s): what a run writes and what the frames' readers take (lidar_frames.hpp).
inline constexpr double kFrameTimeTolerance_s = 1e-6;

struct LidarRunConfig {
    std::string sensor = "vlp16";
    std::string returns;
    double rate_hz = 0;
    int columns = 0;
    double from_s = NAN, to_s = NAN;
    uint64_t seed = 1;
};

/// @brief Whether a scan run with `sensor` is a 3D lidar's: a lidar preset's name or file that
/// is not the name or type of a sensor of the scene (`smokescan scan --sensor`, record bags).
bool isLidarRun(const Scene& scene, const std::string& sensor);

class LidarRun {
public:
    /// @brief Sets the run up: the preset, its rate, columns and return mode, the frame count
    /// (at most limits::kFrames), checked before any work.
    /// @param scene must outlive the run
    /// @throw Error naming the option at fault
    LidarRun(const Scene& scene, const LidarRunConfig& cfg);
    ~LidarRun();
    LidarRun(const LidarRun&) = delete;
    LidarRun& operator=(const LidarRun&) = delete;

    const LidarSpec& spec() const { return spec_; }
    ReturnMode mode() const { return mode_; }
    const SensorMount& mount() const { return mount_; }
    /// The scene's surfaces as the run traces them (another scanner in the same scene reuses them).
    const SurfaceSet& surfaces() const { return *surfaces_; }
    /// The run's scanner (a diagnosis replays recorded frames with it).
    const LidarScanner& scanner() const { return *scanner_; }
    long long frames() const { return frames_; }
    /// The scene time frame k starts at [s].
    double frameStart(long long k) const { return from_s_ + double(k) * (1 / spec_.rate_hz); }
    /// Points a frame holds at most: every beam with every echo the mode keeps.
    long long maxPointsPerFrame() const;

    /// @brief Makes every frame in time order and hands each to `sink`.
    /// @param control progress after each frame; cancel asked before each (throws Cancelled)
    void run(const std::function<void(LidarFrame&&)>& sink, const RunControl& control = {}) const;
    /// @brief Every frame, kept. @throw Error when their points could exceed
    /// limits::kKeptReadings (before any is made); Cancelled as run().
    std::vector<LidarFrame> collect(const RunControl& control = {}) const;

private:
    const Scene& scene_;
    LidarSpec spec_;
    ReturnMode mode_ = ReturnMode::Strongest;
    SensorMount mount_;
    double from_s_ = 0;
    long long frames_ = 0;
    std::unique_ptr<SurfaceSet> surfaces_;
    std::unique_ptr<LidarScanner> scanner_;
};

}  // namespace smokescan
