#include "smokescan/pipeline/omnirange_run.hpp"

#include <atomic>
#include <string>
#include <utility>

#include "smokescan/core/limits.hpp"
#include "watched.hpp"

namespace smokescan {
namespace {

std::string span(const Scene& scene)
{
    return std::to_string(scene.t_start_s) + "…" + std::to_string(scene.t_end_s) + " s";
}

std::vector<double> frameTimes(const OmnirangeRunConfig& a, const Scene& scene)
{
    if (!(a.rate_hz > 0) || !std::isfinite(a.rate_hz)) throw Error("--rate", "must be a finite number > 0 [Hz]");
    const double from = std::isnan(a.from_s) ? scene.t_start_s : a.from_s,
                 to = std::isnan(a.to_s) ? scene.t_end_s : a.to_s;
    if (!std::isfinite(from) || !std::isfinite(to)) throw Error("--from", "and --to must be finite numbers [s]");
    scene.checkSpan(from, to);
    const double n = std::floor((to - from) * a.rate_hz + 1e-9) + 1;
    if (n > double(limits::kFrames))
        throw Error("--rate", "would render over " + std::to_string(limits::kFrames) + " frames");
    std::vector<double> t;
    for (long long k = 0; k < (long long)n; ++k) t.push_back(from + double(k) / a.rate_hz);
    return t;
}

}  // namespace

OmnirangeRun::OmnirangeRun(const Scene& scene, const OmnirangeRunConfig& cfg) : cfg_(cfg)
{
    if (cfg.train_s.empty() == cfg.histogram.empty())
        throw Error("--train", "give either --train TIMES or --histogram FILE");
    if ((long long)cfg.train_s.size() > limits::kFrames) throw Error("--train", "too many training times");
    surfaces_ = std::make_unique<SurfaceSet>(scene);
    times_ = frameTimes(cfg, scene);
    for (double t : cfg.train_s)
        if (!(t >= scene.t_start_s && t <= scene.t_end_s))
            throw Error("--train", "time " + std::to_string(t) + " s lies outside the scene's " + span(scene));
    hist_ = cfg.histogram.empty() ? ColourHistogram(13) : ColourHistogram::load(cfg.histogram);
    // A saved histogram's colours hold at the exposure it learned them at.
    if (!(cfg_.run.exposure > 0) && hist_.exposure() > 0) cfg_.run.exposure = hist_.exposure();
    cfg_.run.watch = &watch_;
    run_ = std::make_unique<OmniRun>(scene, *surfaces_, cfg_.run);
}

OmnirangeRun::~OmnirangeRun() = default;

namespace {

/// n units of work, unit(k) each; with a control, on another thread watched from this one (the
/// frames' renders stopped through `watch`).
void units(size_t n, const std::function<void(size_t)>& unit, RenderWatch& watch, const RunControl& control)
{
    checkCancel(control);
    std::atomic<long long> done{0};
    auto work = [&] {
        for (size_t k = 0; k < n; ++k) {
            unit(k);
            done = (long long)k + 1;
        }
        return 0;
    };
    if (control.cancel || control.progress)
        detail::runWatched<int>(
            work, watch, [&] { return std::pair<long long, long long>(done, (long long)n); }, control);
    else
        work();
}

}  // namespace

void OmnirangeRun::train(const RunControl& control)
{
    const std::vector<double>& t = cfg_.train_s;
    units(
        t.size(), [&](size_t k) { trained_ += run_->train(hist_, t[k], uint64_t(k)); }, watch_, control);
    if (hist_.total() == 0) throw Error("--train", "no free floor pixels to train on (the laser saw no free floor)");
}

void OmnirangeRun::run(const std::function<void(OmniFrame&&)>& sink, const RunControl& control)
{
    // Keys apart from the training frames': a run with the histogram saved from this one reads
    // the same frames.
    units(
        times_.size(), [&](size_t k) { sink(run_->read(hist_, times_[k], (uint64_t(1) << 32) + k)); }, watch_, control);
}

}  // namespace smokescan
