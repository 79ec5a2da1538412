#pragma once
/// @file sensor_config.hpp
/// @brief What a mounted sensor is: its type, its model and every parameter of that model,
/// typed and parsed once. A scene's `[[sensor]]` and a sensor file fill it; a BeamModel is built
/// from it (sensors/beam_model.hpp). Depends on nothing but core, so the scene can hold it.
///
/// Paper model (sensors/paper_model.hpp):
///
/// | parameter          | default | unit       | meaning                                           |
/// |--------------------|---------|------------|---------------------------------------------------|
/// | penetration_power  | 0.007   | density·m  | the paper's 0.0028 × 2.5 m; USARSim's code used 0.00575 |
/// | local_threshold    | 0.002   | density    | local (plume) density at which a beam counts as meeting a particle |
///
/// LMS200 options: `resolution_deg` 1 or 0.5 (default 0.5), `range_mode_m` 8 (mm) or 80 (cm), default 8.
/// Physical model: sensors/physical_params.hpp. Learned extensions of the paper model: sensors/extensions.hpp.
#include <string>

#include "smokescan/sensor_config/extensions.hpp"
#include "smokescan/sensor_config/physical_params.hpp"
#include "smokescan/sensor_config/sensor_kind.hpp"

namespace smokescan {

/// The paper model's two parameters.
struct PaperModelConfig {
    double penetration_power = 0.007;  ///< [density·m]
    double local_threshold = 0.002;  ///< [density]
};

/// The LMS200's scan options.
struct LmsOptions {
    double resolution_deg = 0.5;  ///< 1 or 0.5
    double range_mode_m = 8.0;  ///< 8 (mm unit) or 80 (cm unit)
};

/// A sensor's type, model and parameters.
struct SensorConfig {
    SensorType type = SensorType::Urg04lx;
    SensorModel model = SensorModel::Paper;
    std::string sensor_file;  ///< sensor file the parameters came from ("" = built-in defaults)
    PaperModelConfig paper;
    LmsOptions lms;
    PhysicalParams physical;  ///< defaults per type: physicalDefaults
    ModelExtensions extensions;  ///< learned by `smokescan diagnose` (sensors/extensions.hpp)

    /// @brief The built-in configuration of a sensor type (paper model, calibrated physical defaults).
    static SensorConfig defaults(SensorType type);
};

}  // namespace smokescan
