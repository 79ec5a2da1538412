#include "replay_model.hpp"

#include <algorithm>
#include <cmath>

#include "smokescan/core/error.hpp"

namespace smokescan::detail {

ReplayModel::ReplayModel(const Replay& r, ModelExtensions e) : ext(std::move(e))
{
    surface.assign(r.surface_names.size(), SurfaceExtension{});
    for (const auto& [name, x] : ext.surfaces) {
        const auto it = std::find(r.surface_names.begin(), r.surface_names.end(), name);
        if (it == r.surface_names.end())
            throw Error(r.config.sensor_file.empty() ? std::string("sensor") : r.config.sensor_file,
                        "[extensions] name surface '" + name + "', which the scene does not have");
        surface[size_t(it - r.surface_names.begin())] = x;
    }
    for (const ReplayBeam& b : r.beams) dropout.push_back(ext.dropoutAt(b.angle_rad * 180 / M_PI));
    ln_p = r.isPhysical() ? 0.0 : std::log(r.config.paper.penetration_power);
    offset_change_s = ext.clock_offset_s - r.offset_s;
    const bool shifted = r.from_saturation && offset_change_s != 0;
    for (const ReplayScan& s : r.scans) {
        ln_density_sd.push_back(shifted ? r.lnDensitySdAt(s.time_s + offset_change_s) : s.ln_density_sd);
        density.push_back(shifted ? r.densityAt(s.time_s + offset_change_s) : s.density);
        width.push_back(std::hypot(ext.threshold_width, ln_density_sd.back()));
    }
}

}  // namespace smokescan::detail
