#pragma once
// Internal: a model of the diagnosis on its replay.
#include <vector>

#include "smokescan/diagnose/replay.hpp"
#include "smokescan/sensor_config/extensions.hpp"

namespace smokescan::detail {

/// A sensor's extensions (ModelExtensions, the one form a model has) resolved on the replay for
/// the likelihood's inner loop: its surfaces' by surface index, its sectors' dropout by beam, and
/// its clock offset as the change to the one the replay assumed. Built again after each change.
struct ReplayModel {
    ModelExtensions ext;
    std::vector<SurfaceExtension> surface;  ///< by surface index (zeros: none of its own)
    std::vector<double> dropout;  ///< by beam
    double offset_change_s = 0;  ///< ext.clock_offset_s − the replay's offset_s
    /// Each scan's standard error of ln(density) on the model's clock (the replay's own when the
    /// offset is unchanged).
    std::vector<double> ln_density_sd;
    /// Each scan's smoke density on the model's clock (the replay's own when the offset is
    /// unchanged) and its threshold's width, hypot(threshold_width, ln_density_sd): read once
    /// per scan, not per beam.
    std::vector<double> density, width;
    /// The threshold's ln P before the shifts: ln of the paper model's penetration power, 0 for
    /// the physical model (whose threshold is its own).
    double ln_p = 0;

    /// @brief Resolves `e` on the replay. @throw Error naming the sensor file for a surface the
    /// scene lacks.
    ReplayModel(const Replay& r, ModelExtensions e);
};

}  // namespace smokescan::detail
