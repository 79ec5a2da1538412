// The extensions' beam rule shared by the URG's models, and the physical model with extensions:
// the smoke's threshold moved by scaling the regional smoke the receiver sees.
#include "extension_rule.hpp"

#include <algorithm>
#include <cmath>

#include "beam_models.hpp"
#include "smokescan/core/random.hpp"
#include "smokescan/scene/scene.hpp"
#include "smokescan/scene/surfaces.hpp"

namespace smokescan {

BeamExtension extensionOf(const ModelExtensions& e, const BeamWorld& w, const LaserBeam& beam, const SurfaceHit& hit)
{
    const SurfaceExtension* own = nullptr;
    if (hit.surface >= 0 && !e.surfaces.empty()) {
        const auto it = e.surfaces.find(w.scene.surfaces[size_t(hit.surface)].name);
        if (it != e.surfaces.end()) own = &it->second;
    }
    BeamExtension x;
    x.dropout = e.dropoutAt(beam.angle_rad * 180 / M_PI);
    x.threshold_shift = e.thresholdShift(own, w.smoke_rising);
    x.range_bias = own ? own->range_bias : 0.0;
    return x;
}

// ---- the physical model with extensions ----
//
// A threshold moved by a factor e^s (a surface's factor, the hysteresis) is the receiver seeing
// the regional smoke scaled by e^−s; the onset's spread w scales it by a further e^(w·z) per
// beam, z a standard normal draw. The rest is as in the paper model: a dropout sector, a share q
// of the errors reading short (uniform on (0, L)), the surface's range bias and the noise grown
// with the smoke column C on the receiver's reading.

BeamResult PhysicalBeamModel::readExtended(const BeamWorld& w, const LaserBeam& beam, KeyedRng* rng) const
{
    const ModelExtensions& e = config().extensions;
    const SurfaceHit hit = w.surfaces.closest(beam.ray, spec().range_max_m);
    if (hit.surface < 0) return readPlain(w, beam.ray, rng);  // nothing to extend: no surface in range
    // The draws, or their medians for the noise-free reading.
    double u_drop = 0.5, z = 0, u_ret = 0.5, u_short = 0.5, noise = 0;
    if (rng) {
        u_drop = rng->uniform();
        z = rng->normal();
        u_ret = rng->uniform();
        u_short = rng->uniform();
        noise = rng->normal();
    }
    const BeamExtension x = extensionOf(e, w, beam, hit);
    // The column to the central ray's surface, as the diagnosis replays it (the receiver's own
    // trace runs over the footprint, to its farthest hit).
    BeamQuery q;
    q.wavelength_nm = spec().wavelength_nm;
    const BeamSmoke to_surface = w.field.trace(beam.ray, 0.0, hit.t_m, q);
    if (u_drop < x.dropout) {
        BeamResult r;
        r.hit = hit;
        r.smoke = to_surface;
        return markError(r, spec().no_return_code, "sector_dropout");
    }
    const double scale = std::exp(-x.threshold_shift + e.threshold_width * z);
    const SmokeField scaled = w.field.scaledRegional(scale);
    BeamResult r = readPlain(BeamWorld{w.scene, w.surfaces, scaled, w.smoke_rising}, beam.ray, rng);
    r.smoke = to_surface;  // the smoke the beam met (before the threshold's scaling)
    const double L = hit.t_m, C = to_surface.column_regional;
    if (r.error) {
        if (u_ret >= e.smoke_obstacle_return) return r;
        r.error = false;
        r.cause = "smoke_obstacle";
        return reportRange(spec(), std::max(u_short * L, spec().range_min_m), 0.0, r);
    }
    const double measured =
        extended::rangeMean(double(r.value) * spec().unit_m, x.range_bias, C) + e.range_noise_growth_m * C * noise;
    r.value = std::llround(std::max(measured, spec().range_min_m) / spec().unit_m);
    if (spec().isErrorValue(r.value)) return markError(r, spec().no_return_code, "out_of_range");
    return r;
}

double PhysicalBeamModel::errorProbabilityExtended(const BeamWorld& w, const LaserBeam& beam) const
{
    const ModelExtensions& e = config().extensions;
    const SurfaceHit hit = w.surfaces.closest(beam.ray, spec().range_max_m);
    if (hit.surface < 0) return errorProbabilityPlain(w, beam.ray);
    const BeamExtension x = extensionOf(e, w, beam, hit);
    double p = 0;  // over the onset's spread: the normal's quantiles (core/quadrature.hpp)
    const double* z = normalNodes();
    for (int i = 0; i < kNormalNodes; ++i) {
        const SmokeField scaled = w.field.scaledRegional(std::exp(-x.threshold_shift + e.threshold_width * z[i]));
        p += errorProbabilityPlain(BeamWorld{w.scene, w.surfaces, scaled, w.smoke_rising}, beam.ray) / kNormalNodes;
    }
    return extended::errorShare(x.dropout, p, e.smoke_obstacle_return);
}

}  // namespace smokescan
