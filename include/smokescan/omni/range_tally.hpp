#pragma once
/// @file range_tally.hpp
/// @brief Readings against the truth, binned by the smoke column the sensor looks through: how
/// often a rangefinder fails and how far off it reads as smoke thickens (experiments/omnicam_smoke).
///
/// A reading is **ok** when it lies within tolerance_m of the truth, or, with the truth beyond the
/// sensor's maximum range, when it gives no range or reads at least max_range − tolerance_m;
/// **short** when it reads nearer (smoke, or floor taken for an obstacle); **long** when it reads
/// farther (an obstacle missed: seen through, or taken for floor); **none** when it gives no range
/// (an error value) where the truth lies within its range. The failure rate is the share of readings
/// that are not ok. The range error is |reading − truth| over the readings with a range whose truth
/// lies within the maximum range (failures included: it is what a map built from them would carry).
///
/// | parameter    | default | unit      | meaning                                                 |
/// |--------------|---------|-----------|---------------------------------------------------------|
/// | tolerance_m  | 0.3     | m         | ok within this of the truth (cloud_profile's obstacle margin) |
/// | column_edges | 0, 1e-4, 3e-4, 1e-3, 3e-3, 0.01, 0.03, 0.1, +inf | density·m | the bins' lower edges, then the last's upper |
#include <string>
#include <vector>

namespace smokescan {

enum class ReadingOutcome { Ok, Short, Long, None };

/// @brief One reading's outcome.
/// @param reading_m the reading; NaN when the sensor gave no range (an error value)
/// @param truth_m the true range; +inf when nothing lies within reach
ReadingOutcome classifyReading(double reading_m, double truth_m, double max_range_m, double tolerance_m);

struct RangeTallyConfig {
    double tolerance_m = 0.3;
    std::vector<double> column_edges = {0, 1e-4, 3e-4, 1e-3, 3e-3, 0.01, 0.03, 0.1, 1e300};
};

/// Counts in one column bin.
struct RangeTallyBin {
    long long readings = 0, ok = 0, shorter = 0, longer = 0, none = 0;
    long long ranged = 0;  ///< readings with a range whose truth lies within the maximum range
    double sum_abs_m = 0;  ///< Σ|reading − truth| over those

    double failureRate() const { return readings ? 1.0 - double(ok) / double(readings) : 0.0; }
    double meanAbsM() const { return ranged ? sum_abs_m / double(ranged) : 0.0; }
};

/// One sensor's readings over a run.
class RangeTally {
public:
    /// @throw Error for a tolerance that is not positive and finite, or edges that do not rise
    /// from 0 (at least two).
    RangeTally(std::string sensor, double max_range_m, RangeTallyConfig cfg = {});

    /// @brief Adds one reading (NaN: no range) of a target at truth_m behind `column` of smoke.
    void add(double column, double truth_m, double reading_m);

    const std::string& sensor() const { return sensor_; }
    const RangeTallyConfig& config() const { return cfg_; }
    const std::vector<RangeTallyBin>& bins() const { return bins_; }
    /// All bins summed.
    RangeTallyBin total() const;
    /// @brief A table: one line per non-empty bin (column range, readings, failure rate by kind,
    /// the ranges read where the truth is in range and their mean |error|, "-" for none), then
    /// the total.
    std::string table() const;

private:
    std::string sensor_;
    double max_range_m_;
    RangeTallyConfig cfg_;
    std::vector<RangeTallyBin> bins_;
};

}  // namespace smokescan
