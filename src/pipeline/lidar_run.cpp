#include "smokescan/pipeline/lidar_run.hpp"

#include "smokescan/core/format.hpp"
#include "smokescan/core/limits.hpp"

namespace smokescan {

bool isLidarRun(const Scene& scene, const std::string& sensor)
{
    return !sensor.empty() && scene.findSensor(sensor) < 0 && isLidarName(sensor);
}

LidarRun::LidarRun(const Scene& scene, const LidarRunConfig& cfg) : scene_(scene), spec_(lidarSpec(cfg.sensor))
{
    if (!(cfg.rate_hz >= 0) || !std::isfinite(cfg.rate_hz))
        throw Error("--rate", "must be a finite number > 0 (0: the preset's)");
    if (cfg.columns < 0) throw Error("--columns", "must be > 0 (0: the preset's)");
    if (std::isinf(cfg.from_s)) throw Error("--from", "must be a finite number");
    if (std::isinf(cfg.to_s)) throw Error("--to", "must be a finite number");
    configureLidar(spec_, cfg.rate_hz, cfg.columns, "--rate", "--columns");
    // Without a mode asked for, the sensor's own first (strongest where it offers it).
    mode_ = !cfg.returns.empty()              ? parseReturnMode(cfg.returns, "--returns")
        : spec_.offers(ReturnMode::Strongest) ? ReturnMode::Strongest
                                              : spec_.return_modes.front();
    mount_ = defaultLidarMount(scene, spec_.name);
    from_s_ = std::isnan(cfg.from_s) ? scene.t_start_s : cfg.from_s;
    const double to = std::isnan(cfg.to_s) ? from_s_ : cfg.to_s;
    scene.checkSpan(from_s_, to);  // frames start within the scene's time; the last ends by its end (below)
    const double wanted = std::floor((to - from_s_) * spec_.rate_hz + 1e-9) + 1;
    if (wanted > double(limits::kFrames))
        throw Error(
            "--to",
            "would make " + limits::count(wanted) + " lidar frames (at most " + std::to_string(limits::kFrames) + ")");
    frames_ = (long long)wanted;
    surfaces_ = std::make_unique<SurfaceSet>(scene_);
    scanner_ = std::make_unique<LidarScanner>(scene_, *surfaces_, mount_, spec_, mode_, cfg.seed);
    const auto& pattern = scanner_->pattern();
    const double last_end = frameStart(frames_ - 1) + (pattern.empty() ? 0.0 : pattern.back().time_s);
    // Every frame within the scene's time, as the frames' readers require (lidar_frames.cpp).
    if (last_end > scene.t_end_s + kFrameTimeTolerance_s)
        throw Error(std::isnan(cfg.to_s) ? "--from" : "--to",  // the option that set the last frame
                    fmt("the last frame, from %.12g s, ends at %.12g s, after the scene's end, %.12g s",
                        frameStart(frames_ - 1), last_end, scene.t_end_s));
}

LidarRun::~LidarRun() = default;

long long LidarRun::maxPointsPerFrame() const
{
    return (long long)framePattern(spec_).size() * (mode_ == ReturnMode::Dual ? 2 : 1);
}

void LidarRun::run(const std::function<void(LidarFrame&&)>& sink, const RunControl& control) const
{
    for (long long k = 0; k < frames_; ++k) {
        checkCancel(control);
        sink(scanner_->frame(frameStart(k), uint64_t(k)));
        reportProgress(control, k + 1, frames_);
    }
}

std::vector<LidarFrame> LidarRun::collect(const RunControl& control) const
{
    const double points = double(frames_) * double(maxPointsPerFrame());
    if (points > double(limits::kKeptReadings))
        throw Error("--to",
                    limits::count(double(frames_)) + " frames of the " + spec_.name + " could keep " +
                        limits::count(points) + " points in memory (at most " + std::to_string(limits::kKeptReadings) +
                        "; a shorter span)");
    std::vector<LidarFrame> out;
    out.reserve(size_t(frames_));
    run([&](LidarFrame&& f) { out.push_back(std::move(f)); }, control);
    return out;
}

}  // namespace smokescan
