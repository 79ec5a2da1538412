// The smoke paper's rule for the URG-04LX (paper_model.hpp), and the same rule with the
// extensions a diagnosis learned (extensions.hpp).
#include <algorithm>
#include <cmath>

#include "../beam_models.hpp"
#include "../extension_rule.hpp"
#include "smokescan/scene/scene.hpp"
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

BeamResult PaperUrgModel::rule(const BeamWorld& w, const LaserBeam& beam, const SurfaceHit& hit, const BeamSmoke& smoke,
                               const PaperDraws& d) const
{
    const ModelExtensions& e = config().extensions;
    if (!e.changesBeams()) return paperUrgBeam(spec(), config().paper, hit, smoke, d.noise);
    BeamResult r;
    r.hit = hit;
    r.smoke = smoke;
    if (std::isfinite(smoke.first_local_m)) return markError(r, spec().no_return_code, "local_smoke");
    if (hit.surface < 0) return markError(r, spec().no_return_code, "out_of_range");
    const BeamExtension x = extensionOf(e, w, beam, hit);
    const double lnP = std::log(config().paper.penetration_power) + x.threshold_shift;
    if (d.u_dropout < x.dropout) return markError(r, spec().no_return_code, "sector_dropout");
    const double C = smoke.column_regional, L = hit.t_m;
    if (C > 0 && std::log(C) > lnP + e.threshold_width * d.z_threshold) {
        if (d.u_return >= e.smoke_obstacle_return) return markError(r, spec().no_return_code, "penetration_power");
        r.cause = "smoke_obstacle";  // a short return off the smoke, uniform on (0, L)
        return reportRange(spec(), std::max(d.u_short * L, spec().range_min_m), 0.0, r);
    }
    // The surface's range with its bias and the noise grown with the smoke; the window is the true
    // range's, as the plain model's (reportRange), so extensions do not move the range limits.
    if (reportRange(spec(), L, 0.0, r).error) return r;
    const double sd = std::sqrt(extended::rangeVariance(spec().rangeSigma(L), e.range_noise_growth_m, C));
    const double measured = extended::rangeMean(L, x.range_bias, C) + sd * d.noise;
    r.value = std::llround(std::max(measured, spec().range_min_m) / spec().unit_m);
    if (spec().isErrorValue(r.value)) return markError(r, spec().no_return_code, "out_of_range");
    return r;
}

double PaperUrgModel::ruleErrorProbability(const BeamWorld& w, const LaserBeam& beam, const BeamResult& r) const
{
    const ModelExtensions& e = config().extensions;
    if (!e.changesBeams()) return PaperBeamModel::ruleErrorProbability(w, beam, r);
    if (std::isfinite(r.smoke.first_local_m) || r.hit.surface < 0) return 1.0;
    const BeamExtension x = extensionOf(e, w, beam, r.hit);
    const double lnP = std::log(config().paper.penetration_power) + x.threshold_shift;
    const double ps = extended::stopProbability(r.smoke.column_regional, lnP, e.threshold_width);
    return extended::errorShare(x.dropout, ps, e.smoke_obstacle_return);
}

}  // namespace smokescan
