// The URG-04LX's beam models (its kind: src/sensor_config/kinds/urg04lx.cpp).
#include "../beam_models.hpp"

namespace smokescan {

std::unique_ptr<BeamModel> makeUrg04lxModel(const SensorConfig& c)
{
    if (c.model == SensorModel::Physical) return std::make_unique<AmcwUrgModel>(c);
    return std::make_unique<PaperUrgModel>(c);
}

}  // namespace smokescan
