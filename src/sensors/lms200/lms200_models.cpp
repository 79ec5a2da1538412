// The LMS200's beam models (its kind: src/sensor_config/kinds/lms200.cpp).
#include "../beam_models.hpp"

namespace smokescan {

std::unique_ptr<BeamModel> makeLms200Model(const SensorConfig& c)
{
    if (c.model == SensorModel::Physical) return std::make_unique<PulsedSickModel>(c);
    return std::make_unique<PaperSickModel>(c);
}

}  // namespace smokescan
