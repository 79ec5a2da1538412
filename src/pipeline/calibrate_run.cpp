#include "smokescan/pipeline/calibrate_run.hpp"

#include <atomic>
#include <string>
#include <utility>

#include "smokescan/core/limits.hpp"
#include "watched.hpp"

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
    CalibrationResult r;
    if (control.cancel || control.progress) {
        // The sweep on a thread of its own, stopped within a tile of any frame when asked.
        RenderWatch watch;
        CalibrateConfig watched = cfg;
        watched.watch = &watch;
        std::atomic<long long> frames{0};
        r = detail::runWatched<CalibrationResult>(
            [&] { return calibrate(scene, watched, [&](int done, int) { frames = done; }); }, watch,
            [&] { return std::pair<long long, long long>(frames, (long long)cfg.densities.size()); }, control);
    } else {
        r = calibrate(scene, cfg);
    }
    if (!r.fit.converged)
        throw Error("calibrate",
                    "the curve could not be fitted to these " + std::to_string(cfg.densities.size()) +
                        " points: " + r.fit.message + " (the default sweep: 14 densities from 0 to 0.012)");
    return r;
}

}  // namespace smokescan
