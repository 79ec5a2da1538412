#pragma once
/// @file omni_rangefinder.hpp
/// @brief The omnidirectional camera as a colour-based rangefinder (Nguyen and Visser): polar
/// scanlines from the image centre outwards, each pixel free floor or not by the colour
/// histogram, the first obstacle's image radius ρ turned into a floor distance d = h·tan θ with
/// θ = 2·arctan(ρ/R); and its training from laser scans taken at the same pose.
///
/// | parameter    | default | unit | meaning                                                     |
/// |--------------|---------|------|-------------------------------------------------------------|
/// | scanlines    | 360     | –    | scanlines, evenly spaced in azimuth from 0 (local +x)        |
/// | filter       | N 20, K 2 | px | the scanline filters (scanline.hpp)                          |
/// | threshold    | 0.05    | –    | Θ ∈ (0, 1]: a pixel is free when its bin's share ≥ Θ         |
/// | height_m     | 0.931   | m    | the viewpoint's height above the floor (the paper's robot)   |
/// | min_range_m  | 0.3     | m    | nearer hit points read as this (the robot's own footprint)   |
/// | max_range_m  | 3.8     | m    | no hit point, or one beyond it, reads as this (the paper's)  |
#include <string>
#include <vector>

#include "smokescan/io/image.hpp"
#include "smokescan/omni/colour_histogram.hpp"
#include "smokescan/omni/scanline.hpp"
#include "smokescan/render/omni_camera.hpp"

namespace smokescan {

struct OmniRangeConfig {
    int scanlines = 360;
    ScanlineFilter filter;
    double threshold = 0.05;
    double height_m = 0.931;
    double min_range_m = 0.3;
    double max_range_m = 3.8;
};

/// What one scanline read.
enum class OmniRangeStatus { Hit, MinRange, MaxRange };

struct OmniRangeResult {
    std::vector<double> angle_rad;  ///< azimuth from local +x towards local +y
    std::vector<double> range_m;  ///< floor distance from below the viewpoint
    std::vector<OmniRangeStatus> status;
    std::vector<double> hit_radius_px;  ///< image radius of the hit (NaN when none)
};

/// @brief Refuses a configuration that cannot work with this camera, one line naming the key:
/// scanlines outside 1…36000, Θ outside (0, 1], N or K below 1 (or above 10000), a height or
/// range that is not positive and finite, a minimum range not below the maximum, or a mirror or
/// mount that puts the floor at the maximum range (with N pixels behind it) outside the image,
/// beyond the mirror's rim or at the horizon. @throw Error
void checkOmniRangeConfig(const OmniRangeConfig& cfg, const OmniCamera& cam);

/// @brief Reads one frame: a range per scanline.
/// @param frame display-encoded RGB in [0, 1] (as `render` writes frames), the camera's size
/// @throw Error for a bad configuration (checkOmniRangeConfig) or a frame of another size.
OmniRangeResult omniRange(const Image& frame, const OmniCamera& cam, const ColourHistogram& hist,
                          const OmniRangeConfig& cfg);

/// One laser scan at the same moment as the frame, in the laser's frame.
struct LaserFreeSpace {
    Pose pose;  ///< the laser's pose in the world (its beams in its local xy plane)
    std::vector<double> angle_rad;  ///< beam azimuths, increasing
    std::vector<double> range_m;  ///< measured ranges; NaN (an error value) marks no free space
};

/// @brief Training: counts into `hist` the colours of the frame's floor pixels that the laser
/// saw free — floor points (on the plane height_m below the viewpoint) nearer than the laser's
/// range at their bearing by more than margin_m and within max_range_m of the viewpoint.
/// @param skip_scanline when given (cfg.scanlines entries), pixels whose bearing from the
/// camera's axis lies nearest a scanline marked true are left out (the outliers, below)
/// @return the number of pixels counted
/// @throw Error for a frame of another size, an empty scan or a skip list of another length.
long long trainFreeSpace(ColourHistogram& hist, const Image& frame, const OmniCamera& cam, const LaserFreeSpace& laser,
                         const OmniRangeConfig& cfg, double margin_m = 0.1,
                         const std::vector<bool>* skip_scanline = nullptr);

}  // namespace smokescan
