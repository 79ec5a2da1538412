#include "smokescan/omni/omni_run.hpp"

#include <cmath>

#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/omni/omni_compare.hpp"
#include "smokescan/render/renderer.hpp"

namespace smokescan {

OmniRun::OmniRun(const Scene& scene, const SurfaceSet& surfaces, const OmniRunConfig& cfg)
    : scene_(scene), surfaces_(surfaces), cfg_(cfg), exposure_(cfg.exposure)
{
    const Camera* found = nullptr;
    for (const Camera& c : scene.cameras)
        if (c.kind == CameraKind::Omni && (cfg.camera.empty() || c.name == cfg.camera)) {
            found = &c;
            break;
        }
    if (!found)
        throw Error(scene.source,
                    cfg.camera.empty() ? "the scene has no omni camera (kind = \"omni\")"
                                       : "no omni camera named '" + cfg.camera + "'");
    cam_ = *found;
    if (cfg.spp < 1 || cfg.spp > limits::kSpp) throw Error("--spp", "must lie in 1…" + std::to_string(limits::kSpp));
    if (int64_t(cam_.width) * cam_.height > limits::kFramePixels)
        throw Error(cam_.name, "frame over " + std::to_string(limits::kFramePixels) + " pixels");
    if (!(cfg.margin_m >= 0) || !std::isfinite(cfg.margin_m)) throw Error("margin_m", "must be finite and >= 0");
    if (!std::isfinite(cfg.floor_z_m)) throw Error("floor_z_m", "must be finite");
    if (!(cfg.outlier_m >= 0.01 && cfg.outlier_m <= 100)) throw Error("--outlier", "must lie in [0.01, 100] m");
    ScanConfig sc;
    sc.sensor = cfg.laser;
    sc.seed = cfg.seed;
    sc.from_s = sc.to_s = scene.t_start_s;  // each frame's scan is taken at its own time (scanAt)
    sc.rate_hz = 1;
    scanner_ = std::make_unique<Scanner>(scene, surfaces, sc);
    if (!(std::abs(cfg.exposure) <= 1e6) || (cfg.exposure > 0 && cfg.exposure < 1e-6))
        throw Error("--exposure", "must lie in [1e-6, 1e6] (<= 0: metered)");
    // The distance formula takes the mirror's axis as vertical.
    const Pose cp = scene.cameraAt(cam_, scene.t_start_s).pose;
    if (!((cp.R * Vec3(0, 0, -1)).z() < -std::cos(M_PI / 180)))
        throw Error(scene.source, "omni camera '" + cam_.name + "' must look straight down (tilted more than 1°)");
    if (!(scene.sensorAt(scanner_->mount(), scene.t_start_s).pose.t.z() > cfg.floor_z_m))
        throw Error("--floor-z", "puts the floor above the laser");
    checkOmniRangeConfig(rangeAt(scene.t_start_s), cameraAt(scene.t_start_s));
}

const OmniCamera& OmniRun::cameraAt(double t_s)
{
    model_ = makeCamera(scene_.cameraAt(cam_, t_s));
    return dynamic_cast<const OmniCamera&>(*model_);
}

OmniRangeConfig OmniRun::rangeAt(double t_s) const
{
    OmniRangeConfig r = cfg_.range;
    r.height_m = scene_.cameraAt(cam_, t_s).pose.t.z() - cfg_.floor_z_m;
    if (!(r.height_m > 0))
        throw Error(cam_.name, "the omni camera is not above the floor at t = " + std::to_string(t_s) + " s");
    if (r.height_m > 100)
        throw Error("--floor-z",
                    "puts the floor over 100 m below the omni camera at t = " + std::to_string(t_s) + " s");
    return r;
}

Image OmniRun::render(double t_s, uint64_t k)
{
    RenderConfig rc;
    rc.time_s = t_s;
    rc.spp = cfg_.spp;
    rc.seed = cfg_.seed * 1000003 + k;
    rc.progress = false;
    rc.watch = cfg_.watch;
    const CameraModel& cam = cameraAt(t_s);
    const RenderResult rr = smokescan::render(scene_, surfaces_, cam, rc);
    if (rr.stopped) throw Error("omnirange", "stopped");
    double used = 0;
    Image display = toDisplay(rr.radiance, exposure_, &used, &cam);
    exposure_ = used;  // metered once, then held: the histogram's colours stay comparable
    return display;
}

LaserFreeSpace OmniRun::laserAt(double t_s, uint64_t k, std::vector<long long>* values) const
{
    const Scan s = scanner_->scanAt(t_s, k);
    if (values) *values = s.value;
    LaserFreeSpace l;
    l.pose = scene_.sensorAt(scanner_->mount(), t_s).pose;
    const LrfSpec& spec = scanner_->spec();
    for (size_t i = 0; i < s.value.size(); ++i) {
        l.angle_rad.push_back(s.angle_rad[i]);
        l.range_m.push_back(spec.rangeOf(s.value[i]));
    }
    return l;
}

long long OmniRun::train(ColourHistogram& hist, double t_s, uint64_t k)
{
    const Image frame = render(t_s, k);
    hist.setExposure(exposure_);
    const OmniCamera& cam = cameraAt(t_s);
    const OmniRangeConfig rc = rangeAt(t_s);
    const LaserFreeSpace laser = laserAt(t_s, k);
    // The paper's outlier rejection: a trial histogram with this frame's counts reads the frame;
    // scanlines whose reading lies over outlier_m from the laser's (e.g. where the laser saw free
    // floor under an overhang the camera sees from above) are left out of the counts.
    ColourHistogram trial = hist;
    trainFreeSpace(trial, frame, cam, laser, rc, cfg_.margin_m);
    if (trial.total() == 0) return 0;
    OmniFrame f;
    f.omni = omniRange(frame, cam, trial, rc);
    f.laser_angle_rad = laser.angle_rad;
    f.laser_range_m = laser.range_m;
    f.laser_pose = laser.pose;
    f.camera_pose = cam.pose();
    const std::vector<double> l = laserPerScanline(f);
    std::vector<bool> skip(f.omni.range_m.size(), false);
    for (size_t s = 0; s < skip.size(); ++s) {
        // A reading at the minimum range is one too; one at the maximum is "at least that far",
        // comparable only with a laser range short of it.
        const bool comparable =
            std::isfinite(l[s]) && (f.omni.status[s] != OmniRangeStatus::MaxRange || l[s] < rc.max_range_m);
        skip[s] = comparable && std::abs(l[s] - f.omni.range_m[s]) > cfg_.outlier_m;
    }
    return trainFreeSpace(hist, frame, cam, laser, rc, cfg_.margin_m, &skip);
}

OmniFrame OmniRun::read(const ColourHistogram& hist, double t_s, uint64_t k, Image* frame_out)
{
    Image frame = render(t_s, k);
    OmniFrame f;
    f.time_s = t_s;
    f.omni = omniRange(frame, cameraAt(t_s), hist, rangeAt(t_s));
    const LaserFreeSpace l = laserAt(t_s, k, &f.laser_value);
    f.laser_angle_rad = l.angle_rad;
    f.laser_range_m = l.range_m;
    f.laser_pose = l.pose;
    f.camera_pose = scene_.cameraAt(cam_, t_s).pose;
    if (frame_out) *frame_out = std::move(frame);
    return f;
}

}  // namespace smokescan
