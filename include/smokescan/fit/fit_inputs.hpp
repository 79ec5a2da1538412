#pragma once
/// @file fit_inputs.hpp
/// @brief Everything a fit of recorded data reads, assembled once: the laser log, the camera's
/// saturation (one patch's column when asked), the calibration, the sensor and its beam groups
/// (from a scene, a groups file or angle ranges). `smokescan fit` and `smokescan diagnose` start here.
///
/// | field         | default   | meaning                                                            |
/// |---------------|-----------|--------------------------------------------------------------------|
/// | laser         | –         | the recorded laser log (io/recorded.hpp), or:                      |
/// | bag, topic    | –, ""     | a ROS 2 bag's LaserScan topic ("" = its only one; bag/bag_input.hpp) |
/// | saturation    | –         | the camera's saturation CSV                                        |
/// | calibration   | "bocas"   | calibration JSON or built-in name                                  |
/// | patch         | ""        | use this patch's column (and its calibration curve) as the saturation |
/// | scene         | ""        | scene whose surfaces name the beam groups                           |
/// | sensor        | ""        | the scene's sensor by name ("" = the first of sensor_type)          |
/// | sensor_type   | "urg04lx" | the sensor type without a scene                                    |
/// | prefix        | "target_" | surfaces whose names start with it form the groups                  |
/// | surfaces_file | ""        | beam groups from a file (beam_groups.hpp)                          |
/// | surfaces      | –         | beam groups as "name=a0:a1@range" (replace the scene's)            |
/// | read          | mm, strict| the log's unit and --lenient                                       |
#include <memory>
#include <string>
#include <vector>

#include "smokescan/calib/saturation_curve.hpp"
#include "smokescan/fit/beam_groups.hpp"
#include "smokescan/fit/fit_report.hpp"
#include "smokescan/io/recorded.hpp"
#include "smokescan/scene/scene.hpp"
#include "smokescan/scene/surfaces.hpp"
#include "smokescan/sensor_config/laser_kind.hpp"

namespace smokescan {

/// What a recorded log came from, as `--sensor-type` names it: a laser kind
/// (sensor_config/laser_kind.hpp), or the omnicam (omnirange's log, fitted by fit/omni_fit.hpp).
struct RecordedSensor {
    const LaserKind* laser = nullptr;  ///< null: the omnicam
    bool omnicam() const { return laser == nullptr; }
};
/// @brief The sensor named `name`. @throw Error naming --sensor-type for an unknown name.
RecordedSensor recordedSensor(const std::string& name);

struct FitInputsConfig {
    std::string laser, saturation, calibration = "bocas", patch;
    std::string scene, sensor, sensor_type = "urg04lx", prefix = "target_", surfaces_file;
    std::vector<std::string> surfaces;
    ReadOptions read;
    std::string bag, topic;  ///< in place of `laser`
    /// When `saturation` is a bag (bag/bag_input.hpp: isBagPath): its Image topic ("" = the only
    /// one) and the target's patches, "NAME=x,y,w,h" rects and "NAME=x1,y1,…" polygons [px].
    std::string image_topic;
    std::vector<std::string> rects, polygons;
};

struct FitInputs {
    RecordedLog log;
    SaturationSeries saturation;  ///< the series the fit uses (the patch's column when asked)
    CurveFitResult calibration;
    SensorMount mount;  ///< the scene's sensor, or the type's defaults
    std::unique_ptr<Scene> scene;  ///< null without --scene
    std::unique_ptr<SurfaceSet> surfaces;
    std::vector<BeamGroup> groups;
    FitSources sources;  ///< for the report: files, groups' origin, skipped lines
    double sigma_t_per_density =
        NAN;  ///< the scene's regional smoke extinction at the laser's wavelength [1/m]; NaN without a scene

    FitInputs() = default;
    FitInputs(FitInputs&&) = default;
    FitInputs& operator=(FitInputs&&) = default;
};

/// @brief Exactly one of --laser and --bag (and --topic only with --bag): the source's name for
/// messages. @throw Error naming the option otherwise.
std::string scansSource(const std::string& laser, const std::string& bag, const std::string& topic);

/// @brief The series with one patch's column as its saturation (rows where the patch has no value
/// left out). @throw Error naming the file when there is no such patch or it has no values.
SaturationSeries patchSeries(const SaturationSeries& s, const std::string& patch);

/// @brief Reads the files alone: the log, the saturation, the calibration and the scene (no sensor,
/// no groups). @throw Error naming the file at fault.
FitInputs loadFitData(const FitInputsConfig& cfg);

/// @brief Reads and assembles the inputs. @throw Error naming the file or option at fault.
FitInputs loadFitInputs(const FitInputsConfig& cfg);

}  // namespace smokescan
