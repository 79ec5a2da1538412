#pragma once
/// @file omnirange_run.hpp
/// @brief `smokescan omnirange` as a library run: the omnidirectional camera as a colour-based
/// rangefinder beside a laser (the omnicam paper; docs/omnicam.md). Its floor colours are learned
/// from the laser's free space at the training times (or read from a saved histogram), then each
/// frame's ranges are read.
///
/// | field     | default          | unit | meaning                                                   |
/// |-----------|------------------|------|-----------------------------------------------------------|
/// | run       | OmniRunConfig's  | –    | camera, laser, spp, seed, rangefinder (omni/omni_run.hpp)  |
/// | train_s   | {}               | s    | times the laser's scan trains the colour histogram, or    |
/// | histogram | ""               | –    | a saved histogram (one of the two)                        |
/// | from_s, to_s | NaN (the scene's span) | s | the frames' times                                 |
/// | rate_hz   | 1                | Hz   | frames per second                                         |
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "smokescan/omni/colour_histogram.hpp"
#include "smokescan/omni/omni_run.hpp"
#include "smokescan/pipeline/run_control.hpp"

namespace smokescan {

struct OmnirangeRunConfig {
    OmniRunConfig run;
    std::vector<double> train_s;
    std::string histogram;
    double from_s = NAN, to_s = NAN, rate_hz = 1;
};

class OmnirangeRun {
public:
    /// @brief Sets the run up, checked before any work: the times, the training times or the
    /// histogram, the camera and laser. @param scene must outlive the run
    /// @throw Error naming the option at fault
    OmnirangeRun(const Scene& scene, const OmnirangeRunConfig& cfg);
    ~OmnirangeRun();

    /// The frames' times [s], scene clock.
    const std::vector<double>& times() const { return times_; }
    /// @brief Learns the floor's colours at the training times (nothing with a saved histogram).
    /// @param control progress after each training frame. With a control the frames are rendered
    /// on another thread while the calling thread reports and asks cancel about every 50 ms (a
    /// cancel stops the frame being rendered within a pixel)
    /// @throw Error when no free floor pixel was seen; Cancelled
    void train(const RunControl& control = {});
    /// @brief Reads every frame in time order and hands each to `sink` (train() first); with a
    /// control, as train(), the sink then called on the thread that renders.
    /// @throw Cancelled
    void run(const std::function<void(OmniFrame&&)>& sink, const RunControl& control = {});

    const ColourHistogram& histogram() const { return hist_; }
    long long trainedPixels() const { return trained_; }
    OmniRun& omni() { return *run_; }
    const SurfaceSet& surfaces() const { return *surfaces_; }

private:
    OmnirangeRunConfig cfg_;
    std::unique_ptr<SurfaceSet> surfaces_;
    ColourHistogram hist_;
    RenderWatch watch_;  ///< the frames' renders, stopped from the calling thread
    std::unique_ptr<OmniRun> run_;
    std::vector<double> times_;
    long long trained_ = 0;
};

}  // namespace smokescan
