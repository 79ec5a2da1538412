#include "smokescan/pipeline/calibrate_run.hpp"

#include <string>

#include "smokescan/core/limits.hpp"

namespace smokescan {

CalibrationResult runCalibration(const Scene& scene, const CalibrateConfig& cfg, const RunControl& control)
{
    if (cfg.densities.size() > size_t(limits::kCalibrationDensities))
        throw Error("--densities", "at most " + std::to_string(limits::kCalibrationDensities) + " densities");
    for (double d : cfg.densities)
        if (!(d >= 0 && d <= limits::kCalibrationDensityMax))
            throw Error("--densities",
                        "density " + std::to_string(d) + " is outside [0, " +
                            std::to_string(limits::kCalibrationDensityMax) +
                            "] (the calibration's range; 0.0028 is the paper's threshold)");
    const double per_frame =
        double(cfg.width) * cfg.height * (cfg.field.meter_spp + double(cfg.field.max_batches) * cfg.field.batch_spp);
    if (per_frame * double(cfg.densities.size()) > double(limits::kFrameSamples))
        throw Error("--spp",
                    "width × height × spp × --max-batches × densities is over " +
                        std::to_string(limits::kFrameSamples) + " samples");
    checkCancel(control);
    CalibrationResult r = calibrate(scene, cfg, [&](int done, int total) {
        reportProgress(control, done, total);
        checkCancel(control);
    });
    if (!r.fit.converged)
        throw Error("calibrate",
                    "the curve could not be fitted to these " + std::to_string(cfg.densities.size()) +
                        " points: " + r.fit.message + " (the default sweep: 14 densities from 0 to 0.012)");
    return r;
}

}  // namespace smokescan
