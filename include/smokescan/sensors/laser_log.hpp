#pragma once
/// @file laser_log.hpp
/// @brief The smoke paper's laser log: one scan per line, the time [s] then pairs of
/// (angle [rad], range), whitespace separated; lines starting with '#' are comments.
/// smokescan writes ranges in millimetres (error codes as the sensor's raw values).
#include <ostream>
#include <string>
#include <vector>

#include "smokescan/io/recorded.hpp"
#include "smokescan/sensors/scanner.hpp"

namespace smokescan {

/// @brief The log's header: each line becomes a '#' comment.
void writeLaserLogHeader(std::ostream& out, const std::vector<std::string>& header);
/// @brief One scan as one line of the log (values converted to mm).
void writeLaserLogScan(std::ostream& out, const Scan& scan, const LrfSpec& spec);

/// @brief Writes scans (values converted to mm) atomically. `header` lines become '#' comments.
void writeLaserLog(const std::string& path, const std::vector<std::string>& header, const std::vector<Scan>& scans,
                   const LrfSpec& spec);

/// @brief Reads a laser log strictly: a one-line error naming FILE:LINE for a line with an odd
/// number of fields after the time, a non-numeric or non-finite field, or time going backwards.
std::vector<LaserLogScan> readLaserLog(const std::string& path);

/// @brief Per-beam optical depth table: time_s, beam, angle_rad, value, error, surface,
/// hit_m, column_regional (density·m), column_local (density·m), tau (at the sensor's wavelength).
void writeBeamCsv(const std::string& path, const std::vector<Scan>& scans, const Scene& scene);
/// @brief The per-beam table's column names, and one scan's rows (streaming form of writeBeamCsv).
void writeBeamCsvHeader(std::ostream& out);
void writeBeamCsvScan(std::ostream& out, const Scan& scan, const Scene& scene);

/// @brief A scan series as the smoke paper's Fig. 10 draws it: one row per scan (time downwards),
/// one column per beam (in beam order), grey level = range (darker = shorter, white = beyond
/// `range_max_m`), red = error code. Each beam is `beam_px` pixels wide, each scan `scan_px` tall.
void writeScanImage(const std::string& path, const std::vector<Scan>& scans, const LrfSpec& spec, double range_max_m,
                    int beam_px = 2, int scan_px = 2);

}  // namespace smokescan
