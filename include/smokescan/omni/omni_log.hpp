#pragma once
/// @file omni_log.hpp
/// @brief The omnirange logs (`smokescan omnirange --out`, `--laser-out`): the laser log's format
/// (sensors/laser_log.hpp: a line a scan, time_s then pairs of angle_rad and range in mm), which
/// readRecordedLog reads back (the omnicam's `fit` and `diagnose`).
#include <ostream>
#include <string>

#include "smokescan/omni/omni_run.hpp"

namespace smokescan {

/// @brief The omnicam's log header: the scene, the camera, what trained it, its settings, the format.
/// @param trained e.g. "23249 pixels at 0,1" or a histogram file's name
void writeOmniLogHeader(std::ostream& o, const std::string& scene_source, const std::string& camera,
                        const std::string& trained, const OmniRangeConfig& range);
/// @brief One frame's omnicam ranges: time_s [s], then angle_rad and range [mm] per scanline.
void writeOmniLogScan(std::ostream& o, const OmniFrame& f);
/// @brief The laser's log at the omnicam's times: its header (with its error codes).
void writeOmniLaserLogHeader(std::ostream& o, const std::string& scene_source, const Scanner& laser);
/// @brief The laser's scan at a frame's time, as `scan` writes logs (error values kept).
void writeOmniLaserLogScan(std::ostream& o, const OmniFrame& f, const LrfSpec& spec);

}  // namespace smokescan
