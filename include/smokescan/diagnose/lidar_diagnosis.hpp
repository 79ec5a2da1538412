#pragma once
/// @file lidar_diagnosis.hpp
/// @brief What a 3D lidar's recorded frames say its simulation gets wrong (docs/diagnosis.md,
/// "A 3D lidar's frames"): each recorded frame against the same frame replayed without noise
/// (LidarScanner::expected), beam by beam, on the beams the replay is sure of (clear:
/// a surface echo far above the threshold, no smoke to speak of). Grouped by channel (ring) and
/// by azimuth in the sensor frame, the frames split into two folds (even and odd frames): each
/// cause's candidate is searched on the even frames and tested on the odd ones, so that the
/// search's choice does not make its own evidence.
///
/// | field         | default | unit | meaning                                                        |
/// |---------------|---------|------|----------------------------------------------------------------|
/// | level         | 0.05    | –    | false-alarm level of the whole diagnosis (Bonferroni over the causes; `--alpha`) |
/// | sector_deg    | 5       | deg  | azimuth bins of the window's sector search                     |
/// | max_sector_deg| 90      | deg  | the widest sector tried                                        |
/// | min_dropout   | 0.1     | –    | floor: the smallest excess of missed returns named (a channel, a sector) |
/// | min_bias_sd   | 1       | –    | floor: the smallest channel range bias named, in the datasheet's range sd |
///
/// Causes (LidarCause), on the clear beams: a dropping channel (dead or weak: returns missing on
/// one ring, all azimuths), a dirty-window sector (returns missing on every ring within a span of
/// azimuth), a biased channel (one ring's ranges offset from the others'); on the beams that are
/// not clear, against the replay's chances under the receiver's noise: smoke echoes taken as first
/// returns (more short returns than the replay gives, all frames: nothing is searched), a
/// surface's threshold (a surface returned more or less often than its chance, given the return is
/// not short). A cause is named when its held-out test passes at level/5 and its held-out effect
/// reaches its floor (min_dropout for the shares).
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <map>
#include <string>
#include <vector>

#include "smokescan/fit/lidar_fit.hpp"
#include "smokescan/lidar/lidar_scanner.hpp"

namespace smokescan {

struct LidarDiagnosisConfig {
    double level = 0.05;
    double sector_deg = 5;
    double max_sector_deg = 90;
    double min_dropout = 0.1;
    double min_bias_sd = 1;
};

enum class LidarCause { DroppingChannel, WindowSector, BiasedChannel, SmokeFirstReturns, SurfaceThreshold };
const char* lidarCauseName(LidarCause c);

/// One cause's candidate, searched on the even frames and tested on the odd ones.
struct LidarFinding {
    LidarCause cause = LidarCause::DroppingChannel;
    int ring = -1;  ///< the channel (DroppingChannel, BiasedChannel)
    int surface = -1;  ///< the surface (SurfaceThreshold): Scene::surfaces index
    double from_deg = 0, to_deg = 0;  ///< the sector's azimuths in the sensor frame (WindowSector)
    /// Held out: excess missed share (channel, sector), range bias [m], excess short share (smoke
    /// first returns), surface returns' share over their chance (surface threshold; < 0: fewer)
    double effect = 0, effect_se = 0;
    double floor = 0;  ///< the cause's floor in the effect's unit
    /// Dropouts (channel, sector): the other clear beams' missed share on the held-out frames, the
    /// rate the excess is over (the dropout that gives the excess is effect / (1 − base_rate)).
    double base_rate = 0;
    double gain_nats = 0;  ///< held-out log-likelihood gain of the candidate over none
    double p_value = 1;  ///< held out; one-sided for dropouts and smoke returns, else two-sided
    bool named = false;  ///< p < level/5 and |effect| at least its floor
    bool tested = false;  ///< false: no candidate (no beams or no excess on the search fold)
};

/// One channel's or sector's beams over both folds.
struct LidarGroupStats {
    long long clear = 0;  ///< clear beams (the replay's certain surface echoes)
    long long missed = 0;  ///< of them, without a recorded return
    long long matched = 0;  ///< of them, with a recorded first return (a range residual)
    double median_residual_m = 0;  ///< recorded − replayed range, median (0 when none matched)
};

/// Recorded outcomes of a kind against the replay's chances of them, over some beams.
struct LidarOutcomes {
    double observed = 0;  ///< beams where it happened
    double expected = 0;  ///< Σ its chance
    double variance = 0;  ///< Σ p(1 − p)(1 + 1/draws), p taken off 0 and 1 as draws of ½ (lidar_tally.cpp)
    long long beams = 0;
    LidarOutcomes& operator+=(const LidarOutcomes& o)
    {
        observed += o.observed, expected += o.expected, variance += o.variance, beams += o.beams;
        return *this;
    }
};

/// What the frames say: counts, group tables, each cause's test and the verdict.
struct LidarDiagnosis {
    size_t frames = 0;
    long long beams = 0, clear = 0, unmatched_points = 0;  ///< unmatched: no beam of that ring near its time
    double range_sd_m = NAN;  ///< the clear beams' residuals' robust sd (1.4826·MAD) [m]; NaN: none
    std::vector<LidarGroupStats> rings;  ///< by channel
    std::vector<LidarGroupStats> sectors;  ///< by azimuth bin from −180°, sector_deg wide
    double sector_deg = 5;
    std::vector<LidarFinding> tried;  ///< one per cause
    /// Per surface seen (index into surface_names): both folds' surface returns against their chance.
    std::map<int, LidarOutcomes> surfaces;
    std::vector<std::string> surface_names;  ///< the scene's surfaces (set by the caller), for reports
    std::string verdict;  ///< "none" or the named causes, comma-separated
    /// The largest difference between a frame's recorded start pose and the scene's pose of the
    /// sensor then (set by the caller that reads the frames): position [m] and angle [deg]; NaN
    /// when the frames carry no pose (a bag's PointCloud2 frames).
    double pose_mismatch_m = 0, pose_mismatch_deg = 0;
    /// Frames empty in effect, left out (set by the caller that reads the frames: TalliedFrames).
    size_t empty_frames = 0;
    std::string sensor, returns, scene;  ///< what was diagnosed (set by the caller), for reports
    /// The frames read (set by the caller): a frames folder or a bag, and the bag's topic ("" for
    /// a folder).
    std::string points, topic;
    /// lidar.toml's text: the diagnosed preset extended by the named findings (set by the caller:
    /// pipeline/lidar_diagnose_run.hpp's extendedLidarPreset)
    std::string extended_preset;
};

/// A recorded point is its beam's when it lies within this angle of the beam's direction [deg].
inline constexpr double kMatchDeg = 1;

/// Counts a run's frames against their replays, beam by beam, in two folds.
class LidarTally {
public:
    /// @param pattern the frame's beams (LidarScanner::pattern)
    /// @param tolerance_m classifyReturn's tolerance (returnTolerance_m of the sensor)
    /// @param max_range_m the sensor's range: a point beyond it (or at no finite range) is no beam's
    LidarTally(const std::vector<PatternBeam>& pattern, int channels, double tolerance_m,
               double max_range_m = INFINITY);
    /// @brief Adds one frame: the replay's beams (in pattern order) and the recorded points
    /// (ring and time from the frame's start identify a point's beam, its direction within
    /// kMatchDeg confirms it; return_index 0 is its first kept return; any other point is
    /// counted unmatched). @param fold 0 (search) or 1 (held out)
    void add(const std::vector<ExpectedBeam>& expected, const std::vector<LidarPoint>& recorded, int fold);
    size_t frames() const { return frames_; }

    using Outcomes = LidarOutcomes;
    struct Fold {
        std::vector<uint32_t> clear, missed;  ///< per beam of the pattern
        /// The same per surface the clear beam's central ray hits (Scene::surfaces index), per beam.
        std::map<int, std::vector<uint32_t>> clear_on, missed_on;
        std::vector<std::vector<float>> residual_m;  ///< per channel: recorded − replayed range
        std::vector<std::vector<int>> residual_surface;  ///< per channel: each residual's surface
        /// Short first returns (smoke before the surface) on beams that are not clear and could
        /// return something.
        Outcomes short_returns;
        /// Per surface (Scene::surfaces index): first returns at the surface, on beams that are
        /// not clear, whose surface's echo the noise could lift over the threshold and whose
        /// recorded return is not short; their chance given not short.
        std::map<int, Outcomes> surface_returns;
    };
    const Fold& fold(int k) const { return fold_[k]; }
    const std::vector<PatternBeam>& pattern() const { return pattern_; }
    int channels() const { return channels_; }
    long long unmatched() const { return unmatched_; }
    /// Every clear beam answered on a surface, both folds: its recorded and replayed intensity
    /// (what `smokescan fit --points` fits, fit/lidar_fit.hpp), kept once asked for (36 bytes a beam).
    const std::vector<LidarIntensitySample>& intensities() const { return intensities_; }
    /// Clear beams answered at their surface whose recorded intensity is not finite or not
    /// positive: left out of intensities() (counted once asked for).
    long long unusableIntensities() const { return unusable_intensities_; }
    void keepIntensities(bool keep) { keep_intensities_ = keep; }

private:
    void addOutcomes(const ExpectedBeam& x, double recorded_m, Fold& f) const;

    std::vector<PatternBeam> pattern_;
    int channels_ = 0;
    double tolerance_m_ = 0, max_range_m_ = INFINITY;
    std::vector<std::vector<std::pair<double, uint32_t>>> by_ring_;  ///< (time, beam), by time
    Fold fold_[2];
    size_t frames_ = 0;
    long long unmatched_ = 0;
    std::vector<LidarIntensitySample> intensities_;
    long long unusable_intensities_ = 0;
    bool keep_intensities_ = false;
};

/// @brief 1.4826 · the median absolute deviation of the residuals in `sets` (each by channel,
/// as LidarTally::Fold::residual_m) [m]; NaN when there are none.
double robustResidualSd(std::initializer_list<const std::vector<std::vector<float>>*> sets);

/// @brief The diagnosis of a tally: group tables and each cause's held-out test.
/// @param range_sigma_m the sensor's datasheet range sd (the bias's floor unit)
/// @throw Error when either fold has no clear beam.
LidarDiagnosis diagnoseLidar(const LidarTally& tally, double range_sigma_m, const LidarDiagnosisConfig& cfg = {});

/// @brief A finding's target as text: "ring 3", "azimuth 10.0..25.0 deg", a surface's name.
std::string lidarFindingTarget(const LidarDiagnosis& d, const LidarFinding& f);
/// @brief The diagnosis as JSON text (diagnosis.json of `smokescan diagnose --points`).
std::string lidarDiagnosisJson(const LidarDiagnosis& d);
/// @brief The diagnosis as a Markdown report (report.md).
std::string lidarDiagnosisMarkdown(const LidarDiagnosis& d, const std::string& sensor);

}  // namespace smokescan
