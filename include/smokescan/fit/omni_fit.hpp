#pragma once
/// @file omni_fit.hpp
/// @brief What `smokescan fit` needs to fit the omnicam rangefinder's log (omni/omni_run.hpp):
/// which of its readings failed, which scanlines see which surface, and the length of the camera's
/// line of sight to each. The omnicam has no error values: in smoke it reads short (or long) where
/// the floor stops matching its colour histogram. A reading therefore fails when it is not ok
/// against the scene's truth for its scanline (omni/scanline_truth.hpp, omni/range_tally.hpp: off by
/// more than the tolerance), and the fit's threshold S* is the saturation at which half the
/// scanlines of a surface read wrong. Its penetration power is ρ(S*) times the median length of
/// the line of sight from the viewpoint to the surface's foot on the floor: the column the camera
/// looks through, as the truth tables bin it.
///
/// The camera must stand still during the log (the groups are bearings that keep their surface).
///
/// | field        | default | unit | meaning                                                        |
/// |--------------|---------|------|----------------------------------------------------------------|
/// | camera       | ""      | –    | the scene's omni camera ("" = the first)                        |
/// | floor_z_m    | 0       | m    | the floor's height: the viewpoint's height above it is h         |
/// | max_range_m  | 3.8     | m    | the rangefinder's maximum range (as the log was made)            |
/// | tolerance_m  | 0.3     | m    | a reading further than this from its truth failed (range_tally's) |
/// | groups       | true    | –    | make the fit's groups (a diagnosis needs none)                   |
#include <string>
#include <vector>

#include "smokescan/fit/fit_inputs.hpp"
#include "smokescan/fit/sensor_fit.hpp"
#include "smokescan/omni/range_tally.hpp"

namespace smokescan {

struct OmniFitConfig {
    std::string camera;
    double floor_z_m = 0;
    double max_range_m = 3.8;
    double tolerance_m = 0.3;
    bool groups = true;  ///< make the fit's groups (a diagnosis needs none)
};

/// The omnicam's log with its truth.
struct OmniFitInputs {
    FitInputs in;  ///< the log, saturation, calibration, scene and groups (mount unused)
    FailureMask failed;  ///< [scan][scanline]: not ok against the truth
    LrfSpec spec;  ///< the log's scanlines as a beam layout (no error values: failures are `failed`); its
        ///< scan period the log's median step
    std::string camera;  ///< the omni camera's name
    double height_m = 0;  ///< the viewpoint above the floor
    std::vector<double> truth_m;  ///< per scanline: horizontal distance to the nearest obstacle (+inf: none)
    std::vector<Ray> sight;  ///< per scanline: the line of sight to the obstacle's foot (at most the maximum range)
    std::vector<double> sight_m;  ///< its length [m]
    std::vector<int> surface;  ///< per scanline: the obstacle's surface (−1: none)
    std::vector<double> pixel_m;  ///< per scanline: one image pixel's metric error at the truth (Fig. 8)
    std::vector<ReadingOutcome> outcome;  ///< [scan · scanlines + scanline]: each reading against its truth
    long long readings = 0, shorter = 0, longer = 0;  ///< all readings; those that failed short, long
};

/// @brief Reads the omnicam's log, the saturation and the scene, and classifies every reading.
/// Groups: `--surface`/`--surfaces` bearings (without a range: the distances are the truth's), else
/// the surfaces named `cfg.prefix`* that the truth puts within the maximum range, each scanline
/// whose neighbours see the same surface. Each group's range_m is its median line of sight.
/// @throw Error (one line, naming the file or option) for a scene without that omni camera, a
/// camera that moves during the log, a group with a range, no group, a configuration out of
/// bounds, or a log whose readings mostly lie beyond the maximum range (the wrong --unit).
OmniFitInputs loadOmniFitInputs(const FitInputsConfig& cfg, const OmniFitConfig& omni);

}  // namespace smokescan
