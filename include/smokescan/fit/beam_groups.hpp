#pragma once
/// @file beam_groups.hpp
/// @brief Which beams of a laser log see which surface: angle intervals by name, from the command
/// line, a file, or a scene (the beams that hit each surface in clear air).
///
/// Command line: `NAME=A0:A1[,A2:A3…][@RANGE_M]`, angles in degrees in the log's convention.
/// File: one group per line, `NAME A0_DEG A1_DEG [RANGE_M]` (repeat a name for more intervals);
/// '#' comments. RANGE_M is the laser–surface distance; without it the fit takes the median
/// valid range of the group's beams in clear air.
#include <string>
#include <utility>
#include <vector>

#include "smokescan/scene/scene.hpp"
#include "smokescan/scene/surfaces.hpp"
#include "smokescan/sensor_config/lrf.hpp"

namespace smokescan {

struct BeamGroup {
    std::string name;
    std::vector<std::pair<double, double>> intervals_rad;  ///< closed [a0, a1], a0 ≤ a1
    double range_m = 0;  ///< laser–surface distance; 0 = unknown (taken from the data)
    std::string material;  ///< scene material, when known

    bool contains(double angle_rad) const;
};

/// @brief Parses `NAME=A0:A1[,A2:A3][@RANGE_M]` (degrees). @throw Error naming `what`.
BeamGroup parseBeamGroup(const std::string& spec, const std::string& what = "--surface");

/// @brief Reads a group file (format above). @throw Error "FILE:LINE: …".
std::vector<BeamGroup> readBeamGroupFile(const std::string& path);

/// @brief Groups the sensor's beams by the surface each hits in clear air. Beams within
/// `edge_beams` of a beam hitting another surface straddle an edge and are left out.
/// @param prefix only surfaces whose names start with it ("" = all)
std::vector<BeamGroup> beamGroupsFromScene(const Scene& scene, const SurfaceSet& surfaces, const SensorMount& mount,
                                           const LrfSpec& spec, const std::string& prefix = "", int edge_beams = 1);

}  // namespace smokescan
