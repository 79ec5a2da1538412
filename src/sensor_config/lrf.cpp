#include "smokescan/sensor_config/lrf.hpp"

#include <cmath>

#include "smokescan/core/error.hpp"
#include "smokescan/sensor_config/sensor_config.hpp"

namespace smokescan {

LrfSpec urg04lx()
{
    LrfSpec s;
    s.type = SensorType::Urg04lx;
    s.wavelength_nm = 785;
    s.n_beams = 725 - 44 + 1;
    s.dangle_rad = 2 * M_PI / 1024;
    s.angle0_rad = (44 - 384) * s.dangle_rad;
    s.range_min_m = 0.02;
    s.range_max_m = 5.6;
    s.unit_m = 0.001;
    s.scan_period_s = 0.1;
    s.no_return_code = urg_code::kNoReturn;
    s.sigma_near_m = 0.005;
    s.near_limit_m = 1.0;
    s.sigma_rel = 0.005;
    return s;
}

LrfSpec lms200(double res_deg, double range_mode_m)
{
    if (res_deg != 1.0 && res_deg != 0.5) throw Error("lms200", "resolution must be 1 or 0.5 degrees");
    if (range_mode_m != 8.0 && range_mode_m != 80.0) throw Error("lms200", "range mode must be 8 or 80 m");
    LrfSpec s;
    s.type = SensorType::Lms200;
    s.wavelength_nm = 905;
    s.n_beams = int(std::lround(180.0 / res_deg)) + 1;
    s.dangle_rad = res_deg * M_PI / 180.0;
    s.angle0_rad = 0.0;
    s.range_min_m = 0.0;
    s.unit_m = range_mode_m == 8.0 ? 0.001 : 0.01;
    s.range_max_m = (lms_code::kNoEcho - 1) * s.unit_m;  // 8183 and above are error values
    s.scan_period_s = 1.0 / 75.0;
    s.no_return_code = lms_code::kNoEcho;  // "measured value > maximum value" (docs/sensors.md)
    s.sigma_near_m = range_mode_m == 8.0 ? 0.005 : 0.01;
    s.near_limit_m = 1e9;
    s.sigma_rel = 0.0;
    return s;
}

bool LrfSpec::isErrorValue(long long v) const
{
    switch (type) {
    case SensorType::Urg04lx:
        return v < urg_code::kFirstRange;
    case SensorType::Lms200:
        return v >= lms_code::kNoEcho;
    }
    return true;
}

std::string LrfSpec::errorValueSummary() const
{
    switch (type) {
    case SensorType::Urg04lx:
        return "values below 20 (0 = no return)";
    case SensorType::Lms200:
        return "values >= 8183 (8183 = no echo within range)";
    }
    return "";
}

LrfSpec specFor(const SensorConfig& c)
{
    switch (c.type) {
    case SensorType::Urg04lx:
        return urg04lx();
    case SensorType::Lms200:
        return lms200(c.lms.resolution_deg, c.lms.range_mode_m);
    }
    throw Error("sensor", "unknown sensor type");
}

}  // namespace smokescan
