#pragma once
/// @file fit_run.hpp
/// @brief `smokescan fit` and `smokescan fit-plume` as library calls: a recorded run and the
/// camera's saturation → the sensor's smoke thresholds, penetration power and clock offset
/// (docs/fitting.md), and a Sick's penetration into plumes; their files written by the caller.
///
/// | field      | default             | meaning                                                      |
/// |------------|---------------------|--------------------------------------------------------------|
/// | in         | FitInputsConfig's   | the log or bag, saturation, calibration, scene or beam groups, sensor (fit/fit_inputs.hpp) |
/// | model      | paper               | the sensor file's model: paper, or physical (the URG-04LX's noise floor solved in the scene) |
/// | fit        | SensorFitConfig's   | offset, link, smoothing, bootstrap, reference group (fit/sensor_fit.hpp) |
/// | omni       | OmniFitConfig's     | the omnicam's classes (--sensor-type omnicam)                 |
/// | omni_given | {}                  | which of --tolerance, --max-range, --floor-z were given       |
/// | on_scene   | none                | called with the scene once it is read, before any work (a caller protecting its files) |
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <string>

#include "smokescan/fit/fit_inputs.hpp"
#include "smokescan/fit/omni_fit.hpp"
#include "smokescan/fit/physical_fit.hpp"
#include "smokescan/fit/plume_fit.hpp"
#include "smokescan/fit/sensor_fit.hpp"
#include "smokescan/pipeline/run_control.hpp"
#include "smokescan/sensor_config/sensor_file.hpp"

namespace smokescan {

struct FitRunConfig {
    FitInputsConfig in;
    SensorModel model = SensorModel::Paper;
    SensorFitConfig fit;
    OmniFitConfig omni;
    std::set<std::string> omni_given;
    std::function<void(const Scene&)> on_scene;
};

/// The omnicam's readings against the scene's truth (fit --sensor-type omnicam).
struct OmniReadings {
    std::string camera;
    double height_m = 0;  ///< the viewpoint above the floor
    long long readings = 0, shorter = 0, longer = 0;
};

struct FitRunResult {
    SensorFitResult fit;
    SensorFitConfig used;  ///< the settings the fit ran with (the scene's σ_t in)
    std::string scans;  ///< the recorded scans' source
    FitInputs inputs;  ///< what was read: log, saturation, calibration, scene, groups
    LrfSpec spec;
    std::optional<UrgNoiseFloorResult> physical;  ///< the physical model's noise floor, when asked and fitted
    std::optional<OmniReadings> omni_readings;
    /// The fitted sensor file (when a threshold was fitted and, for the physical model, its noise
    /// floor): a laser's, or the omnicam's onset; and its header comment.
    std::optional<SensorConfig> laser;
    std::optional<OmniSensorFile> omni;
    std::string sensor_comment;
    bool ok() const { return laser || omni; }
    /// Why there is no sensor file ("" when there is one).
    std::string failure;
};

/// @brief Reads the run's files and fits the sensor. A fit that finds no threshold is a result
/// (its report says why: failure), not an exception. With a control, the fit runs on another
/// thread while the calling thread asks cancel about every 50 ms (a cancel stops it at its next
/// offset step or bootstrap replicate) and reports (1, 1) when it is done; on_scene is called on
/// the thread doing the work.
/// @throw Error naming the file or option at fault; Cancelled
FitRunResult runFit(FitRunConfig cfg, const RunControl& control = {});

/// @brief The fit's JSON report (the _report.json `smokescan fit` writes).
std::string fitRunJson(const FitRunResult& r);

struct PlumeRunConfig {
    std::string laser, bag, topic;  ///< the Sick's log, or a bag and its LaserScan topic
    std::string scene;  ///< with the plumes (a file or built-in name)
    std::string sensor;  ///< the scene's sensor ("" = its first lms200)
    ReadOptions read;
    PlumeFitConfig fit;
    std::function<void(const Scene&)> on_scene;  ///< called once the scene is read, before any work
};

struct PlumeRunResult {
    PlumeFitResult fit;
    std::string source;  ///< the log, or the bag and its topic
    std::unique_ptr<Scene> scene;
    size_t skipped = 0;  ///< bad lines left out (lenient)
};

/// @brief Reads the Sick's log and fits its penetration into the scene's plumes.
/// @throw Error naming the file or option at fault (a fit that fails is a result: fit.ok)
PlumeRunResult runPlumeFit(const PlumeRunConfig& cfg, const RunControl& control = {});

}  // namespace smokescan
