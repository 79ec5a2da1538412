#include "smokescan/sensor_config/beam_pattern.hpp"

#include <algorithm>

namespace smokescan {

std::vector<PatternBeam> planarFan(const LrfSpec& spec)
{
    std::vector<PatternBeam> fan(size_t(std::max(0, spec.n_beams)));
    for (int i = 0; i < spec.n_beams; ++i) fan[size_t(i)].azimuth_rad = spec.angle(i);
    return fan;
}

}  // namespace smokescan
