#pragma once
/// @file beam_pattern.hpp
/// @brief A sensor's beams as data: each beam's direction in the sensor's frame, its channel and
/// its firing time within a scan or frame. The 2D lasers' planar fans and the 3D lidars'
/// patterns (lidar/lidar_spec.hpp) are both lists of these.
#include <vector>

#include "smokescan/sensor_config/lrf.hpp"

namespace smokescan {

/// One beam of a pattern, in the sensor frame (x ahead, y left, z up).
struct PatternBeam {
    double azimuth_rad = 0;  ///< from +x towards +y (a spinning head's at the frame's start plus its turn)
    double elevation_rad = 0;  ///< above the x–y plane
    int channel = 0;  ///< ring
    double time_s = 0;  ///< firing time from the scan's or frame's start
};

/// @brief A 2D laser's scan as a pattern: one beam per step at the laser's angle (its own
/// convention: the LMS200's 0…π with π/2 ahead), in the scan plane, channel 0. Its beams all fire
/// at the scan's time (t = 0): smokescan takes a 2D scan as instantaneous, as the smoke paper does.
std::vector<PatternBeam> planarFan(const LrfSpec& spec);

}  // namespace smokescan
