#pragma once
/// @file camera.hpp
/// @brief Camera models: a map from image points to world rays. The integrator sees only this
/// interface, so other projections (the catadioptric omnidirectional camera of the second paper)
/// are added as new models without touching it.
#include <memory>

#include "smokescan/core/ray.hpp"

namespace smokescan {

struct Camera;

class CameraModel {
public:
    virtual ~CameraModel() = default;
    virtual int width() const = 0;
    virtual int height() const = 0;
    /// @brief The ray through image point (x_px, y_px): pixel (i, j) covers [i, i+1) × [j, j+1),
    /// y downwards. False when the point sees nothing (e.g. outside an omnicam's mirror disc).
    virtual bool generateRay(double x_px, double y_px, Ray& ray) const = 0;
};

/// Pinhole intrinsics [px].
///
/// | field  | meaning                                            |
/// |--------|----------------------------------------------------|
/// | fx, fy | focal lengths in pixels                             |
/// | cx, cy | principal point (image centre: width/2, height/2)  |
struct PinholeIntrinsics {
    int width = 640, height = 480;
    double fx = 0, fy = 0, cx = 0, cy = 0;
    /// Square pixels, principal point at the centre, focal length from the horizontal field of view.
    static PinholeIntrinsics fromHfov(int width, int height, double hfov_deg);
};

/// Looks along its pose's local +x with local +z up (local +y is image left).
class PinholeCamera final : public CameraModel {
public:
    PinholeCamera(const Pose& pose, const PinholeIntrinsics& k);
    int width() const override { return k_.width; }
    int height() const override { return k_.height; }
    bool generateRay(double x_px, double y_px, Ray& ray) const override;
    const PinholeIntrinsics& intrinsics() const { return k_; }

private:
    Pose pose_;
    PinholeIntrinsics k_;
};

/// @brief The camera model for a scene camera. @throw Error for a non-finite pose or bad intrinsics.
std::unique_ptr<CameraModel> makeCamera(const Camera& cam);
/// @brief A pinhole scene camera's intrinsics (its focal lengths, or from its field of view).
/// @throw Error for a focal length that is not finite and > 0.
PinholeIntrinsics pinholeIntrinsics(const Camera& cam);
/// @brief Whether a direction from the camera [world frame] falls within its image (an omnicam:
/// always). @throw Error as pinholeIntrinsics.
bool inView(const Camera& cam, const Vec3& direction);

}  // namespace smokescan
