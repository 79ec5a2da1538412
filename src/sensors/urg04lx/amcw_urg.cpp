// The physical model of the URG-04LX (physical_model.hpp: amcwBeam), as a BeamModel.
#include "../beam_models.hpp"

namespace smokescan {

BeamResult AmcwUrgModel::read(const BeamWorld& w, const Ray& ray, KeyedRng& rng, bool details) const
{
    PhysicalTrace t = physicalTrace(*this, w, ray, details);
    BeamResult r = amcwBeam(spec(), config().physical, t.signal, rng);
    r.hit = t.hit;
    r.smoke = std::move(t.smoke);
    return r;
}

BeamResult AmcwUrgModel::expected(const BeamWorld& w, const Ray& ray) const
{
    PhysicalTrace t = physicalTrace(*this, w, ray, true);
    BeamResult r = amcwBeamExpected(spec(), config().physical, t.signal);
    r.hit = t.hit;
    r.smoke = std::move(t.smoke);
    return r;
}

double AmcwUrgModel::errorProbability(const BeamWorld& w, const Ray& ray) const
{
    return amcwErrorProbability(spec(), config().physical, physicalTrace(*this, w, ray, false).signal);
}

std::string AmcwUrgModel::smokeParameter() const { return namedValue("noise_floor", config().physical.noise_floor); }

}  // namespace smokescan
