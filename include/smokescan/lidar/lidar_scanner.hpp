#pragma once
/// @file lidar_scanner.hpp
/// @brief Frames of a 3D lidar (lidar_spec.hpp) in a scene with smoke: each beam fired from the
/// sensor's pose at its own firing time (the motion distortion a moving robot's lidar has), its
/// received waveform built by the lidar equation (sensors/physical_model.hpp: surfaces over the
/// footprint, smoke along the beam), up to max_echoes echoes resolved in it, and the return mode's
/// echoes kept as points.
///
/// | field      | default   | unit | meaning                                                 |
/// |------------|-----------|------|---------------------------------------------------------|
/// | returns    | strongest | –    | which echoes become points (the sensor must offer it)   |
/// | seed       | 1         | –    | noise seed; frames do not depend on the thread count    |
#include <cstdint>
#include <vector>

#include "smokescan/lidar/lidar_spec.hpp"
#include "smokescan/scene/scene.hpp"
#include "smokescan/scene/surfaces.hpp"
#include "smokescan/sensors/physical_model.hpp"

namespace smokescan {

class KeyedRng;

/// One echo a beam's receiver resolved.
struct LidarEcho {
    double range_m = 0;  ///< leading edge at half maximum plus half the pulse's width [m]
    double peak = 0;  ///< the echo's peak (normalised power: a white Lambertian target at 1 m = 1) above its pedestal
    /// The signal it rose out of (normalised power): 0 for the first peak of a run above the
    /// threshold, the valley before it for a peak that stood out of another's run (waveform_peaks.hpp).
    double pedestal = 0;
    /// What stands out for the noise to undo: the peak for a run's first, else the smaller of its
    /// height and the fall from the previous peak to the valley (normalised power).
    double standout = 0;
    double intensity = 0;  ///< calibrated reflectivity [%]: 100·peak·R²/O(R), at most 255
    EchoSource source = EchoSource::Surface;  ///< what sent most of the echo's power
    /// The peak's noise sd in the samples' (their noise propagated through the log-parabola
    /// through the three samples around it, to first order; about 1), and the valley's sample's
    /// beside it for a peak measured above one (√2). Set without noise (rng null) only.
    double peak_noise = 1;
};

/// @brief The echoes a lidar's receiver resolves in a beam's signal, in order of range: the
/// waveform's peaks (waveform_peaks.hpp) in its runs above threshold_snr × noise, each standing
/// out of the signal before it by as much (with the receiver's noise when `rng` is given), the
/// first peak of a run that starts in the blind zone left out; within the range window, at most
/// max_echoes; each range with the datasheet noise when `rng` is given.
std::vector<LidarEcho> receiveEchoes(const LidarSpec& spec, const BeamSignal& signal, KeyedRng* rng);
/// @brief The same from the beam's noise-free waveform (pulsedWaveform at 2 samples per σ),
/// for draws of the noise on one waveform.
std::vector<LidarEcho> receiveEchoes(const LidarSpec& spec, const BeamSignal& signal, Waveform waveform, KeyedRng* rng);

/// @brief Which of a beam's echoes (indices into `echoes`, in range order) a return mode keeps:
/// first, last, strongest, or dual (strongest and last, or strongest and second strongest, as the
/// sensor defines it; one point when they are the same echo).
std::vector<size_t> selectReturns(const std::vector<LidarEcho>& echoes, ReturnMode mode, bool dual_second_strongest);

/// One point of a frame, with the fields lidar drivers write.
struct LidarPoint {
    float x = 0, y = 0, z = 0;  ///< in the sensor's frame at the beam's firing time [m]
    float range_m = 0;
    float intensity = 0;  ///< calibrated reflectivity [%]
    uint16_t ring = 0;  ///< channel
    uint8_t return_index = 0;  ///< 0: the mode's first point of the beam, 1: its second (dual)
    uint8_t source = 0;  ///< EchoSource: 0 surface, 1 smoke, 2 mirror (ground truth; drivers have none)
    float time_s = 0;  ///< firing time from the frame's start [s]
    uint32_t beam = 0;  ///< the beam's index in the frame's pattern
};

struct LidarFrame {
    uint64_t index = 0;
    double start_s = 0, end_s = 0;  ///< scene time of the frame's first and last firing [s]
    Pose start_pose, end_pose;  ///< the sensor's pose in the world then
    int channels = 0, columns = 0;
    std::vector<LidarPoint> points;  ///< in firing order; beams without an echo give none
    std::vector<float> range_image;  ///< channels × columns: the first kept return's range, 0 none
};

/// Where a beam's first kept return lies against the surface its central ray hits.
enum class ReturnClass { None, Short, Surface, Beyond };

/// @brief A return's class: none (range 0), short (nearer than the surface's echo by more than
/// the tolerance: smoke, or something in front), at the surface (within it), beyond.
/// @param surface_range_m where the surface's echo reads (+inf: no surface in range)
ReturnClass classifyReturn(double range_m, double surface_range_m, double tolerance_m);
/// @brief The tolerance classifyReturn takes for a sensor: half its pulse's FWHM in range and 4
/// range sd.
double returnTolerance_m(const LidarSpec& spec);

/// Noise draws per uncertain beam in LidarScanner::expected, and their seed.
inline constexpr int kOutcomeDraws = 32;
inline constexpr uint64_t kOutcomeSeed = 0x6f7574636f6d65ULL;

/// What a beam's receiver reports without its noise, and the chances of each kind of first
/// return with it: the replay a diagnosis compares recorded frames with
/// (diagnose/lidar_diagnosis.hpp).
struct ExpectedBeam {
    float range_m = 0;  ///< the return mode's first kept echo without noise [m]; 0: none
    float margin_sd = 0;  ///< that echo's peak above the detection threshold, in noise sd
    float peak_sd = 0;  ///< that echo's peak in noise sd (margin_sd + threshold_snr without a pedestal)
    float intensity = 0;  ///< that echo's intensity without noise (LidarEcho::intensity) [%]
    float peak_noise = 1;  ///< that echo's peak's noise in noise sd (LidarEcho::peak_noise)
    /// A clear beam's echo's peak at a half and a quarter of its surfaces' power, over its peak:
    /// ½ and ¼ for an echo alone, more where the smoke's backscatter under it does not scale
    /// (fit/lidar_fit.hpp); 0 when not a clear beam, the echo is lost there, or not asked for
    /// (LidarScanner::expected's `dimmer`).
    float peak_at_half = 0, peak_at_quarter = 0;
    uint8_t source = 0;  ///< that echo's EchoSource
    int surface = -1;  ///< the surface the central ray hits within range (Scene::surfaces), -1 none
    float surface_range_m = INFINITY;  ///< where that surface's echo reads [m]
    /// With the receiver's noise, the chance that the first kept return is none, short or at the
    /// surface (classifyReturn): exact for a clear beam or one whose waveform has no run within
    /// kClearMarginSd noise sd of the threshold, else the shares of kOutcomeDraws draws.
    float p_none = 1, p_short = 0, p_surface = 0;
    /// A surface echo at least kClearMarginSd noise sd above the threshold, and no smoke or
    /// mirror echo even with the threshold kClearMarginSd noise sd lower: the receiver's noise can
    /// neither lose the echo nor add another.
    bool clear = false;
};
inline constexpr double kClearMarginSd = 5;

/// @brief Where a lidar goes in a scene that has no lidar of its own: where the scene's first
/// sensor stands (its position and robot), looking where that sensor looks (the middle of its
/// scan: an LMS200's 90°), or at the origin looking along +x in a scene without sensors.
SensorMount defaultLidarMount(const Scene& scene, const std::string& name);

class LidarScanner {
public:
    /// @param mount where the sensor sits (its pose and robot; its laser config is not used)
    /// @throw Error when the spec does not offer `mode`, or its [extensions.surface] names a
    /// surface the scene does not have.
    LidarScanner(const Scene& scene, const SurfaceSet& surfaces, const SensorMount& mount, LidarSpec spec,
                 ReturnMode mode, uint64_t seed);

    /// @brief The frame starting at scene time start_s; `index` keys its noise. The smoke is the
    /// scene's at the frame's middle (it changes little in a turn of the head).
    LidarFrame frame(double start_s, uint64_t index) const;
    /// @brief Each beam of the frame starting at start_s (in pattern order) as its receiver
    /// reports it without noise, from the same poses and smoke as frame().
    /// @param dimmer also each clear beam's peaks at a half and a quarter of its surfaces' power
    /// (ExpectedBeam::peak_at_half, peak_at_quarter: two more waveforms a clear beam; the fit's)
    std::vector<ExpectedBeam> expected(double start_s, bool dimmer = false) const;
    const LidarSpec& spec() const { return spec_; }
    /// The frame's beams in firing order (direction, channel, time).
    const std::vector<PatternBeam>& pattern() const { return pattern_; }
    double period_s() const { return 1 / spec_.rate_hz; }

private:
    const Scene& scene_;
    const SurfaceSet& surfaces_;
    SensorMount mount_;
    LidarSpec spec_;
    ReturnMode mode_;
    uint64_t seed_;
    std::vector<PatternBeam> pattern_;
    std::vector<Vec3> local_;  ///< each beam's unit direction in the sensor frame
    /// Each surface's reflectance factor (Scene::surfaces index) from [extensions.surface]; empty: none
    std::vector<double> reflectance_;

    /// The frame's timing, poses and smoke (frame() and expected() share them).
    struct FrameSetup;
    FrameSetup setup(double start_s) const;
    /// Beam i's signal in the frame `f`; the central ray's hit into `hit` (may be null).
    /// Into `out`, whose storage is reused.
    void signal(const FrameSetup& f, size_t i, SurfaceHit* hit, BeamSignal& out) const;
    /// Beam i of frame number `index` received: its kept points appended to `out`, its first
    /// into `fr`'s range image (when it has one).
    void beamPoints(const FrameSetup& f, uint64_t index, size_t i, LidarFrame& fr, std::vector<LidarPoint>& out) const;
    /// Beam i of the frame `f` replayed; `low` is the spec with the threshold kClearMarginSd lower.
    ExpectedBeam expectedBeam(const FrameSetup& f, const LidarSpec& low, size_t i, bool dimmer) const;
};

}  // namespace smokescan
