#pragma once
/// @file diagnosis_report.hpp
/// @brief What `smokescan diagnose` writes: diagnosis.json (baseline, findings, extended model,
/// verdict) and report.md (the figures before and after, the findings, every candidate tried, and
/// the residuals against each covariate the simulation knows per beam).
#include <string>

#include "smokescan/diagnose/diagnosis.hpp"

namespace smokescan {

/// Where the run came from, for the report.
struct DiagnosisSources {
    std::string laser, saturation, scene, calibration, sensor_file;
    double offset_s = 0, block_s = 0;
};

/// @brief diagnosis.json's text (docs/diagnosis.md), without its final newline.
std::string diagnosisJson(const DiagnosisResult& r, const DiagnosisSources& src);

/// @brief diagnosis.json, written atomically. Format: docs/diagnosis.md.
void writeDiagnosisJson(const std::string& path, const DiagnosisResult& r, const DiagnosisSources& src);

/// @brief report.md, written atomically, with one plot per finding beside it (finding_N.png): the
/// residuals before and after against the covariate that names the cause.
void writeDiagnosisReport(const std::string& path, const Replay& replay, const DiagnosisResult& r,
                          const DiagnosisSources& src);

/// One row of a residual table: a covariate bin, its observations, and the recorded minus the
/// predicted error share and mean range.
struct ResidualRow {
    std::string bin;
    long long beams = 0;
    double error_share = 0, predicted_error_share = 0;  ///< recorded, and the model's mean P(error)
    double range_residual_m = NAN;  ///< mean (recorded − predicted) over recorded ranges
    double range_rms_m = NAN;  ///< RMS of (recorded − predicted) over recorded ranges
    double predicted_sd_m = NAN;  ///< the model's range standard deviation, RMS over the same
};

/// @brief The residuals of `model` against one covariate: "surface", "incidence_deg", "range_m",
/// "beam_angle_deg", "column", "saturation", "smoke_trend" or "time_s".
/// @param surface only the beams on this surface index (−1: all)
/// @throw Error for an unknown covariate name.
std::vector<ResidualRow> residualsBy(const Replay& replay, const ModelExtensions& model, const std::string& covariate,
                                     int surface = -1);

}  // namespace smokescan
