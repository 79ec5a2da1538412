// The LMS200's receiver in the physical model (physical_model.hpp: first echo of the waveform).
#include "../beam_models.hpp"

namespace smokescan {

BeamResult PulsedSickModel::receive(const BeamSignal& s, KeyedRng* rng) const
{
    return rng ? pulsedBeam(spec(), config().physical, s, *rng) : pulsedBeamExpected(spec(), config().physical, s);
}

double PulsedSickModel::receiveErrorProbability(const BeamSignal& s) const
{
    return pulsedErrorProbability(spec(), config().physical, s);
}

}  // namespace smokescan
