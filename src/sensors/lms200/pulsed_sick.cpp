// The physical model of the LMS200 (physical_model.hpp: pulsedBeam), as a BeamModel.
#include "../beam_models.hpp"

namespace smokescan {

BeamResult PulsedSickModel::read(const BeamWorld& w, const Ray& ray, KeyedRng& rng, bool details) const
{
    PhysicalTrace t = physicalTrace(*this, w, ray, details);
    BeamResult r = pulsedBeam(spec(), config().physical, t.signal, rng);
    r.hit = t.hit;
    r.smoke = std::move(t.smoke);
    return r;
}

BeamResult PulsedSickModel::expected(const BeamWorld& w, const Ray& ray) const
{
    PhysicalTrace t = physicalTrace(*this, w, ray, true);
    BeamResult r = pulsedBeamExpected(spec(), config().physical, t.signal);
    r.hit = t.hit;
    r.smoke = std::move(t.smoke);
    return r;
}

double PulsedSickModel::errorProbability(const BeamWorld& w, const Ray& ray) const
{
    return pulsedErrorProbability(spec(), config().physical, physicalTrace(*this, w, ray, false).signal);
}

std::string PulsedSickModel::smokeParameter() const { return namedValue("noise_floor", config().physical.noise_floor); }

}  // namespace smokescan
