#pragma once
/// @file omni_run.hpp
/// @brief The omnicam rangefinder driven through a scene beside a laser: frames rendered at each
/// time with the scene's omni camera (on its robot, through the scene's smoke), the histogram
/// trained from the laser's scans at chosen times, and a range per scanline at every scan time.
///
/// | parameter     | default | unit | meaning                                                        |
/// |---------------|---------|------|----------------------------------------------------------------|
/// | camera        | ""      | –    | scene camera (kind omni); "" = the first omni camera            |
/// | laser         | ""      | –    | the scene's sensor that trains it; "" = the first               |
/// | spp           | 8       | –    | samples per pixel of each frame                                 |
/// | seed          | 1       | –    | the frames' and the laser's noise                               |
/// | floor_z_m     | 0       | m    | the floor's height: the viewpoint's height above it is h        |
/// | margin_m      | 0.1     | m    | training: floor this much short of the laser's range is free    |
/// | outlier_m     | 1.25    | m    | training: scanlines a trial histogram reads this far from the laser are left out (the paper's); [0.01, 100] |
/// | exposure      | 0       | –    | radiance scale of the frames; ≤ 0: metered once on the first frame, then held (a run reading with a saved histogram takes the histogram's) |
#include <cmath>
#include <string>
#include <vector>

#include "smokescan/io/image.hpp"
#include "smokescan/omni/omni_rangefinder.hpp"
#include "smokescan/render/renderer.hpp"
#include "smokescan/scene/surfaces.hpp"
#include "smokescan/sensors/scanner.hpp"

namespace smokescan {

struct OmniRunConfig {
    std::string camera, laser;
    int spp = 8;
    uint64_t seed = 1;
    double floor_z_m = 0;
    double margin_m = 0.1;
    double outlier_m = 1.25;
    double exposure = 0;
    OmniRangeConfig range;  ///< height_m is set from the camera's pose at each time
    /// When set, each frame's render counts its tiles there, and a stop ends a frame (Error) within
    /// a pixel of its render.
    RenderWatch* watch = nullptr;
};

/// @brief The point range_m along bearing_rad in a pose's local x–y plane (a scan's point).
inline Vec3 scanPlanePoint(const Pose& pose, double bearing_rad, double range_m)
{
    return pose.apply(Vec3(range_m * std::cos(bearing_rad), range_m * std::sin(bearing_rad), 0));
}

/// One time's readings: the omnicam's and the laser's.
struct OmniFrame {
    double time_s = 0;
    OmniRangeResult omni;
    std::vector<double> laser_angle_rad;  ///< in the laser's frame
    std::vector<double> laser_range_m;  ///< NaN for an error value
    std::vector<long long> laser_value;  ///< as the laser reports them (its unit, error values)
    Pose camera_pose, laser_pose;  ///< in the world
};

class OmniRun {
public:
    /// @throw Error (one line) for a scene without an omni camera or a laser, an unknown name,
    /// spp outside 1…65536, a frame over limits::kFramePixels, or a rangefinder configuration
    /// the camera cannot serve (checked at the camera's first pose).
    OmniRun(const Scene& scene, const SurfaceSet& surfaces, const OmniRunConfig& cfg);

    /// @brief Renders the frame and scans with the laser at t_s (k keys the noise), trains
    /// `hist` from them (leaving out the outlier scanlines) and records the frames' exposure in
    /// it; returns the pixels counted.
    long long train(ColourHistogram& hist, double t_s, uint64_t k);
    /// @brief Renders the frame and scans with the laser at t_s; the omnicam's ranges.
    OmniFrame read(const ColourHistogram& hist, double t_s, uint64_t k, Image* frame_out = nullptr);

    const OmniCamera& cameraAt(double t_s);
    /// @brief The rangefinder's configuration at t_s: its height_m the viewpoint's above the floor.
    OmniRangeConfig rangeAt(double t_s) const;
    double exposure() const { return exposure_; }
    const Scanner& laser() const { return *scanner_; }
    const std::string& cameraName() const { return cam_.name; }

private:
    Image render(double t_s, uint64_t k);
    LaserFreeSpace laserAt(double t_s, uint64_t k, std::vector<long long>* values = nullptr) const;

    const Scene& scene_;
    const SurfaceSet& surfaces_;
    OmniRunConfig cfg_;
    Camera cam_;
    std::unique_ptr<Scanner> scanner_;
    std::unique_ptr<CameraModel> model_;
    double exposure_ = 0;
};

}  // namespace smokescan
