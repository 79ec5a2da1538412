// The smoke paper's rule for the URG-04LX (paper_model.hpp), as a BeamModel.
#include "../beam_models.hpp"
#include "smokescan/core/random.hpp"
#include "smokescan/sensors/paper_model.hpp"

namespace smokescan {

BeamResult PaperUrgModel::read(const BeamWorld& w, const Ray& ray, KeyedRng& rng, bool) const
{
    const PaperTrace t = paperTrace(*this, w, ray);
    return paperBeam(spec(), config().paper, t.hit, t.smoke, rng.normal());
}

BeamResult PaperUrgModel::expected(const BeamWorld& w, const Ray& ray) const
{
    const PaperTrace t = paperTrace(*this, w, ray);
    return paperBeam(spec(), config().paper, t.hit, t.smoke, 0.0);
}

double PaperUrgModel::errorProbability(const BeamWorld& w, const Ray& ray) const
{
    const BeamResult r = expected(w, ray);
    return r.error ? 1.0 : reportErrorProbability(spec(), r.true_range_m);
}

std::string PaperUrgModel::smokeParameter() const
{
    return namedValue("penetration_power", config().paper.penetration_power);
}

}  // namespace smokescan
