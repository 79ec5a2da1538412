#pragma once
/// @file recorded.hpp
/// @brief Recorded data as users bring it: laser logs in the smoke paper's format (any range
/// unit) and saturation series (CSV), read strictly or leniently.
///
/// | option  | default | meaning                                                              |
/// |---------|---------|----------------------------------------------------------------------|
/// | unit_m  | 0.001   | the log's range unit [m] ("mm", "cm", "m" by parseRangeUnit)         |
/// | lenient | false   | skip a bad line and record it in `skipped` instead of failing         |
#include <string>
#include <vector>

namespace smokescan {

/// One scan of a laser log (the smoke paper's format: sensors/laser_log.hpp).
struct LaserLogScan {
    double time_s = 0;
    std::vector<double> angle_rad;
    std::vector<double> range;  ///< as written in the file (mm by default)
};

struct ReadOptions {
    double unit_m = 0.001;
    bool lenient = false;
};

/// A line left out under `lenient`: "FILE:LINE" and the problem.
struct SkippedLine {
    std::string where, problem;
};

/// @brief The unit of a name: "mm" → 0.001, "cm" → 0.01, "m" → 1. @throw Error naming `what`.
double parseRangeUnit(const std::string& name, const std::string& what = "--unit");

struct RecordedLog {
    std::string path;
    double unit_m = 0.001;
    std::vector<LaserLogScan> scans;  ///< ranges as written (in unit_m)
    std::vector<SkippedLine> skipped;
};

/// @brief Reads a laser log. Problems, each "FILE:LINE: …": a non-numeric or non-finite field, an
/// odd number of fields after the time, a scan with another beam count than the first (a
/// truncated line), time not advancing, an angle outside ±2π rad, a negative range or one
/// beyond 1 km. The file itself is read within bounds (io/text_input.hpp).
/// @throw Error on the first, unless `lenient`.
RecordedLog readRecordedLog(const std::string& path, const ReadOptions& opt = {});
/// @brief The same from the file's text; `path` names it in errors.
RecordedLog parseRecordedLog(const std::string& text, const std::string& path, const ReadOptions& opt = {});

/// A target's saturation over time (camera clock): the mean over the target and, optionally,
/// per patch (NaN where a frame had no pixels of a patch).
struct SaturationSeries {
    std::string path;
    std::vector<double> time_s, saturation;
    std::vector<std::string> patch_names;
    std::vector<std::vector<double>> patch;  ///< patch[p][k]
    std::vector<SkippedLine> skipped;
    /// Optional spread of each value (a measurement on frames gives them; files may not): the
    /// median and standard deviation over the pixels, and the pixel count. Empty when absent;
    /// else the same shapes as saturation and patch.
    std::vector<double> median, sd, pixels;
    std::vector<std::vector<double>> patch_median, patch_sd;
};

/// @brief Reads `time_s,saturation[,…]` CSV: an optional header (columns by name; `*_median`,
/// `*_sd` and `pixels` are statistics, other extra columns are patches), '#' comments. Problems:
/// too few fields, non-numeric, NaN, saturation outside [0, 1], time going backwards.
/// @throw Error "FILE:LINE: …" unless `lenient`; also when no row is left.
/// @brief Refuses (Error naming `where`) a patch or beam-group name that cannot head a CSV column:
/// empty, over 64 bytes, anything but letters, digits, '_', '-' and '.', or a name the CSV's
/// own columns use (time_s, time, saturation, pixels, ..._median, ..._sd).
void checkColumnName(const std::string& name, const std::string& where);
SaturationSeries readSaturationCsv(const std::string& path, const ReadOptions& opt = {});
/// @brief The same from the file's text; `path` names it in errors.
SaturationSeries parseSaturationCsv(const std::string& text, const std::string& path, const ReadOptions& opt = {});

/// @brief Writes `time_s,saturation` (and patch columns) atomically.
void writeSaturationCsv(const std::string& path, const SaturationSeries& s,
                        const std::vector<std::string>& header = {});

}  // namespace smokescan
