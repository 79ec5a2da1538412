#include "smokescan/sensors/paper_model.hpp"

#include <cmath>

namespace smokescan {

BeamResult paperBeam(const LrfSpec& spec, const PaperModelConfig& cfg, const SurfaceHit& hit, const BeamSmoke& smoke,
                     double noise)
{
    BeamResult r;
    r.hit = hit;
    r.smoke = smoke;
    double range = hit.endOr(kInf);
    switch (spec.type) {
    case SensorType::Urg04lx:
        if (std::isfinite(smoke.first_local_m)) return markError(r, spec.no_return_code, "local_smoke");
        if (smoke.column_regional > cfg.penetration_power)
            return markError(r, spec.no_return_code, "penetration_power");
        break;
    case SensorType::Lms200:
        if (std::isfinite(smoke.first_local_m) && smoke.first_local_m < range)
            range = smoke.first_local_m;  // the Sick sees particle smoke as a solid object
        break;
    }
    return reportRange(spec, range, noise, r);
}

}  // namespace smokescan
