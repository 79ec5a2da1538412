#pragma once
/// @file fit_report.hpp
/// @brief What `smokescan fit` hands back besides the sensor file: a JSON report of every fitted
/// value with its error and every diagnosis, the aligned streams, and plots like the smoke
/// paper's Fig. 5 (saturation and range over time) and Fig. 9 (range and error rate against
/// saturation, with the fitted threshold).
#include <string>
#include <vector>

#include "smokescan/fit/physical_fit.hpp"
#include "smokescan/fit/plume_fit.hpp"
#include "smokescan/fit/sensor_fit.hpp"

namespace smokescan {

/// Where the fitted data came from (for the report).
struct FitSources {
    std::string laser, saturation, calibration, groups_from;
    double unit_m = 0.001;
    std::vector<SkippedLine> skipped;  ///< lines left out under --lenient
};

/// @brief The report as JSON, written atomically.
/// @param physical the physical model's noise floor derived from the fit (null: paper model only)
/// @brief The report's JSON text, without a final newline.
std::string fitReportJson(const SensorFitResult& r, const SensorFitConfig& cfg, const FitSources& src,
                          const UrgNoiseFloorResult* physical = nullptr);
void writeFitReportJson(const std::string& path, const SensorFitResult& r, const SensorFitConfig& cfg,
                        const FitSources& src, const UrgNoiseFloorResult* physical = nullptr);

/// @brief The fit in words, as `smokescan fit` prints it: the clock offset, each group's threshold,
/// penetration power and range bias, notes and diagnoses. `skipped`: bad lines left out.
std::string fitSummaryText(const SensorFitResult& r, size_t skipped);

/// @brief The aligned streams as CSV: time_s, saturation, then per group errors, beams, mean range.
void writeAlignedCsv(const std::string& path, const SensorFitResult& r);

/// @brief Fig. 5: the saturation (camera clock shifted onto the laser's) and the group's mean range
/// over time, error scans marked.
void writeFitTimePlot(const std::string& path, const SensorFitResult& r, int group);

/// @brief Fig. 9: per group, error rate and range against saturation, with the fitted threshold
/// curve and S* marked.
void writeFitSaturationPlot(const std::string& path, const SensorFitResult& r, const SensorFitConfig& cfg);

/// @brief The Sick plume fit as JSON (every value with its error, the bins), written atomically.
/// @brief The plume fit's JSON text, without a final newline.
std::string plumeFitJson(const PlumeFitResult& r, const PlumeFitConfig& cfg, const std::string& laser,
                         const std::string& scene);
void writePlumeFitJson(const std::string& path, const PlumeFitResult& r, const PlumeFitConfig& cfg,
                       const std::string& laser, const std::string& scene);

}  // namespace smokescan
