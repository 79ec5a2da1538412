// The URG-04LX's receiver in the physical model (physical_model.hpp: AMCW phase measurement).
#include "../beam_models.hpp"

namespace smokescan {

BeamResult AmcwUrgModel::receive(const BeamSignal& s, KeyedRng* rng) const
{
    return rng ? amcwBeam(spec(), config().physical, s, *rng) : amcwBeamExpected(spec(), config().physical, s);
}

double AmcwUrgModel::receiveErrorProbability(const BeamSignal& s) const
{
    return amcwErrorProbability(spec(), config().physical, s);
}

double AmcwUrgModel::receiveRangeSigma(const BeamSignal& s) const
{
    return amcwRangeSigma(spec(), config().physical, s);
}

}  // namespace smokescan
