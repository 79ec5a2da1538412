// The smoke paper's rule for the LMS200 (paper_model.hpp).
#include <cmath>

#include "../beam_models.hpp"
#include "smokescan/sensors/paper_model.hpp"

namespace smokescan {

BeamResult paperSickBeam(const LrfSpec& spec, const SurfaceHit& hit, const BeamSmoke& smoke, double noise)
{
    BeamResult r;
    r.hit = hit;
    r.smoke = smoke;
    double range = hit.endOr(kInf);
    if (std::isfinite(smoke.first_local_m) && smoke.first_local_m < range)
        range = smoke.first_local_m;  // the Sick sees particle smoke as a solid object
    return reportRange(spec, range, noise, r);
}

BeamResult PaperSickModel::rule(const BeamWorld&, const LaserBeam&, const SurfaceHit& hit, const BeamSmoke& smoke,
                                const PaperDraws& draws) const
{
    return paperSickBeam(spec(), hit, smoke, draws.noise);
}

}  // namespace smokescan
