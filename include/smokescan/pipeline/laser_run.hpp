#pragma once
/// @file laser_run.hpp
/// @brief A scan run of a scene's 2D laser (URG-04LX, LMS200) as one library call: what
/// `smokescan scan` does, without its files. ScanConfig (sensors/scanner.hpp) in; the scans out,
/// one by one to a sink or kept, with progress and cancellation (pipeline/run_control.hpp).
#include <functional>
#include <memory>
#include <vector>

#include "smokescan/pipeline/run_control.hpp"
#include "smokescan/sensors/scanner.hpp"

namespace smokescan {

class LaserRun {
public:
    /// @brief Sets the run up: the sensor, its model and the scan times, checked before any work.
    /// @param scene must outlive the run
    /// @throw Error for an unknown sensor or model, a bad time span, or more than limits::kScans scans
    LaserRun(const Scene& scene, const ScanConfig& cfg);
    ~LaserRun();
    LaserRun(const LaserRun&) = delete;
    LaserRun& operator=(const LaserRun&) = delete;

    /// The scan times [s], scene clock.
    const std::vector<double>& times() const { return times_; }
    const LrfSpec& spec() const;
    /// The mount with the config's sensor file, model and penetration power applied.
    const SensorMount& mount() const;
    const Scanner& scanner() const { return *scanner_; }
    /// The scene's surfaces, as the run's rays see them.
    const SurfaceSet& surfaces() const { return *surfaces_; }

    /// @brief Makes every scan in time order and hands each to `sink`.
    /// @param control progress after each scan; cancel asked before each (throws Cancelled)
    void run(const std::function<void(Scan&&)>& sink, const RunControl& control = {}) const;
    /// @brief Every scan, kept. @throw Error when they would hold more than
    /// limits::kKeptReadings beams (before any is made); Cancelled as run().
    std::vector<Scan> collect(const RunControl& control = {}) const;

private:
    const Scene& scene_;
    std::unique_ptr<SurfaceSet> surfaces_;
    std::unique_ptr<Scanner> scanner_;
    std::vector<double> times_;
};

}  // namespace smokescan
