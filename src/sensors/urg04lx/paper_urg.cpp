// The smoke paper's rule for the URG-04LX (paper_model.hpp).
#include <cmath>

#include "../beam_models.hpp"
#include "smokescan/sensors/paper_model.hpp"

namespace smokescan {

BeamResult paperUrgBeam(const LrfSpec& spec, const PaperModelConfig& cfg, const SurfaceHit& hit, const BeamSmoke& smoke,
                        double noise)
{
    BeamResult r;
    r.hit = hit;
    r.smoke = smoke;
    if (std::isfinite(smoke.first_local_m)) return markError(r, spec.no_return_code, "local_smoke");
    if (smoke.column_regional > cfg.penetration_power) return markError(r, spec.no_return_code, "penetration_power");
    return reportRange(spec, hit.endOr(kInf), noise, r);
}

BeamResult PaperUrgModel::rule(const SurfaceHit& hit, const BeamSmoke& smoke, double noise) const
{
    return paperUrgBeam(spec(), config().paper, hit, smoke, noise);
}

}  // namespace smokescan
