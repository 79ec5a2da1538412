#pragma once
/// @file trajectory.hpp
/// @brief A robot driven through a scene: its pose keyframed over time. Sensors and cameras that
/// name the robot ride on it, their poses given in its frame (scene-format.md, `[[robots]]`).
///
/// | key (per keyframe) | unit | meaning                                               |
/// |--------------------|------|-------------------------------------------------------|
/// | time_s             | s    | strictly increasing                                   |
/// | position           | m    | the robot frame's origin (on the floor)               |
/// | yaw_deg            | deg  | heading about +z, 0 = world +x                        |
///
/// Between keyframes the position is interpolated linearly and the heading along the shorter
/// arc; before the first and after the last keyframe the robot stands at them.
#include <string>
#include <vector>

#include "smokescan/core/ray.hpp"

namespace smokescan {

struct Keyframe {
    double time_s = 0;
    Vec3 position = Vec3::Zero();
    double yaw_deg = 0;
};

struct Robot {
    std::string name;
    std::vector<Keyframe> keyframes;  ///< at least one, strictly increasing in time

    /// @brief The robot frame's pose in the world at time t_s.
    Pose at(double t_s) const;
    /// @brief The distance driven from the first keyframe to time t_s [m].
    double distanceAt(double t_s) const;
};

}  // namespace smokescan
