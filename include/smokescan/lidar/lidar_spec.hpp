#pragma once
/// @file lidar_spec.hpp
/// @brief A 3D lidar as data: its beams' pattern, timing, range limits, receiver and return modes,
/// read from a preset file (presets/lidar/*.toml, built in) or one of the user's. Adding a
/// spinning lidar is a preset file, not code (docs/lidar.md).
///
/// | key                     | default | unit | meaning                                                    |
/// |-------------------------|---------|------|------------------------------------------------------------|
/// | name                    | –       | –    | the preset's name (`--sensor NAME`)                         |
/// | pattern                 | –       | –    | "spinning" (channels × columns) or "file" (pattern_file)   |
/// | pattern_file            | –       | –    | pattern = "file": CSV azimuth_deg, elevation_deg, time_s[, channel] |
/// | wavelength_nm           | 905     | nm   | laser wavelength (surfaces' NIR reflectivity)              |
/// | spin                    | "cw"    | –    | rotation seen from above: "cw" or "ccw"                    |
/// | rate_hz, rates_hz       | 10, [rate] | Hz | frame rate and the rates the sensor offers                 |
/// | firing_cycle_us         | –       | µs   | a column every cycle (Velodyne): columns = 1/(rate·cycle)  |
/// | columns, columns_allowed| 1024    | –    | columns per turn when no firing cycle is given (Ouster)    |
/// | max_column_rate_hz      | ∞       | Hz   | columns × rate at most                                     |
/// | elevation_deg           | –       | deg  | each channel's elevation, in firing order                  |
/// | elevation_uniform_deg   | –       | deg  | [top, bottom, count]: channels spread uniformly instead    |
/// | azimuth_offset_deg      | 0       | deg  | each channel's azimuth offset                              |
/// | azimuth_offset_cycle_deg| –       | deg  | offsets repeated over the channels                         |
/// | fire_offset_us          | 0       | µs   | each channel's firing time within its column               |
/// | fire_offset_step_us     | 0       | µs   | channel n fires n × step into its column instead           |
/// | range_min_m, range_max_m| 0.5, 100| m    | range window; beyond it no return                          |
/// | range_at_10pct_m        | 50      | m    | a 10 % Lambertian target is detected here ≥ 90 % of the time in clear air: sets the receiver noise |
/// | range_sigma_m           | 0.02    | m    | range noise (1 σ) of a strong echo                         |
/// | divergence_mrad         | 3       | mrad | full beam divergence (the footprint)                       |
/// | pulse_fwhm_ns           | 5       | ns   | pulse width: echoes closer than ~c·FWHM/2 merge            |
/// | threshold_snr           | 6       | –    | an echo is detected above this × the receiver noise        |
/// | return_modes            | all     | –    | the modes the sensor offers: first, last, strongest, dual  |
/// | dual                    | "strongest_last" | – | what dual gives: strongest and last, or "strongest_second" |
/// | max_echoes              | 3       | –    | echoes the receiver resolves per beam (1–8)                |
/// | base                    | –       | –    | a preset (built-in name or file) this one extends: only name and [extensions] besides |
/// | [extensions]            | none    | –    | what a diagnosis learned (LidarExtensions; docs/lidar.md)  |
#include <string>
#include <vector>

#include "smokescan/sensor_config/beam_pattern.hpp"
#include "smokescan/sensor_config/physical_params.hpp"

namespace smokescan {

/// Which of a beam's echoes become points.
enum class ReturnMode { First, Last, Strongest, Dual };
/// @brief "first", "last", "strongest", "dual".
const char* returnModeName(ReturnMode m);
/// @throw Error naming `where` for an unknown name.
ReturnMode parseReturnMode(const std::string& name, const std::string& where);

/// How a lidar fires its beams.
enum class PatternKind { Spinning, File };

/// One channel's departures from the preset ([[extensions.channel]]).
struct LidarChannelExtension {
    int ring = 0;  ///< the channel
    double range_offset_m =
        0;  ///< added to each of its ranges [m], within ±1 m (a range it takes to 0 or less: no point)
    double dropout = 0;  ///< chance that a beam of it returns nothing (a dead or weak channel), 0–1
};

/// A sector of azimuth whose beams return nothing at some rate ([[extensions.sector]]): a dirty
/// or damaged window. Azimuths in the sensor frame within [−180°, 180°]; from > to crosses 180°.
struct LidarSectorExtension {
    double from_deg = 0, to_deg = 0;
    double dropout = 0;  ///< 0–1
    bool contains(double azimuth_rad) const;
};

/// A surface whose echoes are brighter or darker than the scene's reflectance gives
/// ([[extensions.surface]]): its NIR reflectance as the lidar sees it is the scene's times the
/// factor (its diffuse echo, its mirror's share and what its mirror shows alike).
struct LidarSurfaceExtension {
    std::string name;  ///< the scene's surface (Surface::name)
    double reflectance_factor = 1;  ///< 0.01–10 (every surface of that name)
};

/// What `smokescan diagnose --points` and `smokescan fit --points` learned about a lidar, as
/// departures from its preset:
///
/// | table                  | key            | unit | meaning                                   |
/// |------------------------|----------------|------|-------------------------------------------|
/// | [[extensions.channel]] | ring           | –    | the channel (0 … channels − 1)            |
/// |                        | range_offset_m | m    | added to its ranges (±1 m)                |
/// |                        | dropout        | –    | chance a beam of it returns nothing (0–1) |
/// | [[extensions.sector]]  | from_deg, to_deg | deg | azimuths in the sensor frame (±180°)     |
/// |                        | dropout        | –    | chance a beam within returns nothing (0–1)|
/// | [[extensions.surface]] | name           | –    | a surface of the scene the lidar scans    |
/// |                        | reflectance_factor | – | its NIR reflectance × this (0.01–10)     |
struct LidarExtensions {
    std::vector<LidarChannelExtension> channels;
    std::vector<LidarSectorExtension> sectors;
    std::vector<LidarSurfaceExtension> surfaces;
    bool empty() const { return channels.empty() && sectors.empty() && surfaces.empty(); }
    /// @brief The chance that beam (ring, azimuth) returns nothing: its channel's and sectors' dropouts combined.
    double dropout(int ring, double azimuth_rad) const;
    /// @brief What ring's ranges are offset by [m].
    double rangeOffset_m(int ring) const;
};

/// @brief The name of a preset extending `name`: "<name>-extended" (at most 64 bytes, the name
/// cut on a character's boundary), or `name` when it already ends so.
std::string extendedPresetName(const std::string& name);
/// @brief The extensions as TOML ([[extensions.channel]], [[extensions.sector]] and
/// [[extensions.surface]] tables).
std::string lidarExtensionsToml(const LidarExtensions& e);

struct LidarSpec {
    std::string name, source;  ///< preset name; the file it was read from (messages)
    PatternKind pattern = PatternKind::Spinning;
    double wavelength_nm = 905;
    bool clockwise = true;
    double rate_hz = 10;
    std::vector<double> rates_hz;
    double firing_cycle_s = 0;  ///< 0: columns set the column period
    int columns = 1024;
    std::vector<int> columns_allowed;
    double max_column_rate_hz = 0;  ///< 0: no limit
    std::vector<double> elevation_rad, azimuth_offset_rad, fire_offset_s;  ///< per channel
    std::vector<PatternBeam> file_beams;  ///< pattern = file
    std::string pattern_file;  ///< its path (an input of the run)
    double range_min_m = 0.5, range_max_m = 100;
    double range_sigma_m = 0.02;
    int max_echoes = 3;
    std::vector<ReturnMode> return_modes;
    bool dual_second_strongest = false;  ///< dual = strongest + second strongest (else + last)
    PhysicalParams receiver;  ///< footprint, overlap, noise floor, pulse width, threshold
    LidarExtensions extensions;  ///< departures learned by a diagnosis (none in a datasheet preset)
    std::string base;  ///< the preset this one extends (`base`), empty for a whole preset

    int file_channels = 1;  ///< pattern = file: the channels its beams name (the largest + 1)
    int channels() const { return pattern == PatternKind::File ? file_channels : int(elevation_rad.size()); }
    bool offers(ReturnMode m) const;
};

/// Bounds on what a lidar spec may ask for (docs/limits.md).
namespace lidar_limits {
constexpr int kChannels = 512;
constexpr size_t kExtensionSectors = 64;  ///< sectors in a preset's [extensions]
constexpr size_t kExtensionSurfaces = 16384;  ///< surfaces in a preset's [extensions]
constexpr size_t kSurfaceName = 4096;  ///< bytes of a surface's name there
constexpr int kColumns = 8192;
constexpr long long kBeamsPerFrame = 4'000'000;
constexpr double kRateHz = 100;
}  // namespace lidar_limits

/// @brief The built-in presets' names ("hdl32e", "os1-128", "vlp16").
std::vector<std::string> lidarPresetNames();
/// @brief Whether `name` names a preset file (a path ending in .toml), not a built-in preset.
bool isLidarPresetFile(const std::string& name);
/// @brief Whether `name` is a built-in preset or a lidar file (a path ending in .toml).
bool isLidarName(const std::string& name);
/// @brief A built-in preset by name, or a preset file by path.
/// @throw Error naming the file and key for a bad one, or listing the presets for an unknown name.
LidarSpec lidarSpec(const std::string& name_or_path);
/// @brief Parses a preset's text; `source` names it in messages and anchors a relative pattern_file.
LidarSpec parseLidarSpec(const std::string& text, const std::string& source);

/// @brief Sets the frame rate and, when the sensor takes it, the columns (0 keeps the preset's).
/// @param rate_where, columns_where what set each (an option, a file) for errors
/// @throw Error naming `rate_where` for a rate the sensor does not offer, `columns_where` for a
/// column count, both for a combination of the two it cannot fire.
void configureLidar(LidarSpec& spec, double rate_hz, int columns, const std::string& rate_where,
                    const std::string& columns_where);

/// @brief Every beam of one frame, in firing order, with its time from the frame's start.
std::vector<PatternBeam> framePattern(const LidarSpec& spec);
/// @brief Columns in a frame (1 for a pattern file).
int frameColumns(const LidarSpec& spec);

/// @brief Reads a pattern file: CSV lines `azimuth_deg, elevation_deg, time_s[, channel]` ('#'
/// comments), times increasing within [0, 1/rate), at most kBeamsPerFrame beams.
/// @throw Error naming the file and line.
std::vector<PatternBeam> readPatternFile(const std::string& path, double frame_period_s);

}  // namespace smokescan
