#pragma once
/// @file scanline_truth.hpp
/// @brief Ground truth per omnicam scanline (which the omnicam paper did not have): the nearest
/// obstacle along the scanline's bearing between the floor and the viewpoint, and the smoke
/// column the camera looks through to see that obstacle's foot.
///
/// The obstacle is the nearest surface met by horizontal probe rays from the viewpoint's vertical
/// axis at heights probe_step_m, 2·probe_step_m, … above the floor, up to the viewpoint: what a
/// robot as tall as the viewpoint would run into. A cabinet on legs counts at its body's edge; the
/// omnicam, which reads where the floor stops being visible, sees that edge farther out (by
/// h/(h − z) for an edge at height z), and the laser below the body sees through. The distance is
/// horizontal, from the axis.
///
/// The column is ∫ρ ds over all smoke volumes along the camera's line of sight, from the viewpoint
/// to the floor point at that distance (at the maximum range when the obstacle lies beyond it).
///
/// | parameter    | default | unit | meaning                                            |
/// |--------------|---------|------|----------------------------------------------------|
/// | probe_step_m | 0.05    | m    | spacing of the probe rays' heights above the floor |
/// | reach_m      | 50      | m    | probes end here: no obstacle nearer reads +inf     |
#include <vector>

#include "smokescan/core/ray.hpp"

namespace smokescan {

class SurfaceSet;
class SmokeField;

struct ScanlineTruthConfig {
    double probe_step_m = 0.05;
    double reach_m = 50;
};

/// The truth of one frame's scanlines.
struct ScanlineTruth {
    std::vector<double> range_m;  ///< horizontal distance to the nearest obstacle; +inf for none
    std::vector<double> column;  ///< smoke column along the line of sight [density·m]
    std::vector<int> surface;  ///< the nearest obstacle's scene surface index; −1 for none
    std::vector<Ray> sight;  ///< the line of sight from the viewpoint to the obstacle's foot (unit direction)
    std::vector<double> sight_m;  ///< its length [m]
};

/// @brief The truth at each azimuth.
/// @param camera_pose the omni camera's pose in the world (looking straight down)
/// @param height_m the viewpoint's height above the floor
/// @param azimuth_rad scanline azimuths in the camera's frame (OmniRangeResult::angle_rad)
/// @param max_range_m the rangefinder's maximum range: the line of sight ends there at most
/// @throw Error for a height, step or reach that is not positive and finite.
ScanlineTruth scanlineTruth(const SurfaceSet& surfaces, const SmokeField& smoke, const Pose& camera_pose,
                            double height_m, const std::vector<double>& azimuth_rad, double max_range_m,
                            const ScanlineTruthConfig& cfg = {});

}  // namespace smokescan
