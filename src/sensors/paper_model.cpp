#include "smokescan/sensors/paper_model.hpp"

#include <algorithm>
#include <cmath>

namespace smokescan {

BeamResult& markError(BeamResult& r, long long code, const char* cause)
{
    r.error = true;
    r.value = code;
    r.cause = cause;
    return r;
}

BeamResult& reportRange(const LrfSpec& spec, double range, double noise, BeamResult& r)
{
    if (!std::isfinite(range) || range > spec.range_max_m || range < spec.range_min_m)
        return markError(r, spec.no_return_code, "out_of_range");
    r.true_range_m = range;
    const double measured = range + spec.rangeSigma(range) * noise;
    const long long v = std::llround(std::max(measured, spec.range_min_m) / spec.unit_m);
    if (spec.isErrorValue(v)) return markError(r, spec.no_return_code, "out_of_range");
    r.value = v;
    return r;
}

BeamResult paperBeam(const LrfSpec& spec, const PaperModelConfig& cfg, const SurfaceHit& hit,
                     const BeamSmoke& smoke, double noise)
{
    BeamResult r;
    r.hit = hit;
    r.smoke = smoke;
    double range = hit.hit ? hit.t_m : kInf;
    if (spec.type == "urg04lx") {
        if (std::isfinite(smoke.first_local_m)) return markError(r, spec.no_return_code, "local_smoke");
        if (smoke.column_regional > cfg.penetration_power)
            return markError(r, spec.no_return_code, "penetration_power");
    } else if (std::isfinite(smoke.first_local_m) && smoke.first_local_m < range) {
        range = smoke.first_local_m;  // the Sick sees particle smoke as a solid object
    }
    return reportRange(spec, range, noise, r);
}

}  // namespace smokescan
