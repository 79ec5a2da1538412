// The smoke paper's rule for the LMS200 (paper_model.hpp), as a BeamModel.
#include "../beam_models.hpp"
#include "smokescan/core/random.hpp"
#include "smokescan/sensors/paper_model.hpp"

namespace smokescan {

BeamResult PaperSickModel::read(const BeamWorld& w, const Ray& ray, KeyedRng& rng, bool) const
{
    const PaperTrace t = paperTrace(*this, w, ray);
    return paperBeam(spec(), config().paper, t.hit, t.smoke, rng.normal());
}

BeamResult PaperSickModel::expected(const BeamWorld& w, const Ray& ray) const
{
    const PaperTrace t = paperTrace(*this, w, ray);
    return paperBeam(spec(), config().paper, t.hit, t.smoke, 0.0);
}

double PaperSickModel::errorProbability(const BeamWorld& w, const Ray& ray) const
{
    const BeamResult r = expected(w, ray);
    return r.error ? 1.0 : reportErrorProbability(spec(), r.true_range_m);
}

std::string PaperSickModel::smokeParameter() const
{
    return namedValue("penetration_power", config().paper.penetration_power);
}

}  // namespace smokescan
