// The Sick LMS200 as a kind (sensor_config/laser_kind.hpp): pulsed time of flight at 905 nm,
// with its own scan options (resolution and range mode).
#include "smokescan/sensor_config/lms200.hpp"

#include <cmath>

#include "kinds.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/sensor_config/sensor_config.hpp"
#include "toml_reader.hpp"

namespace smokescan {

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
    s.last_range_value = lms_code::kNoEcho - 1;
    s.sigma_near_m = range_mode_m == 8.0 ? 0.005 : 0.01;
    s.near_limit_m = 1e9;
    s.sigma_rel = 0.0;
    return s;
}

namespace {

class Lms200Kind final : public LaserKind {
public:
    SensorType type() const override { return SensorType::Lms200; }
    const char* name() const override { return "lms200"; }
    const char* article() const override { return "an"; }  // "you-ar-gee", "el-em-ess"
    Receiver receiver() const override { return Receiver::Pulsed; }
    LrfSpec spec(const SensorConfig& c) const override { return lms200(c.lms.resolution_deg, c.lms.range_mode_m); }
    std::string errorValueSummary() const override { return "values >= 8183 (8183 = no echo within range)"; }
    float rep117(long long v) const override
    {
        return v == lms_code::kNoEcho ? INFINITY : NAN;  // weak or ambiguous, dazzled: failed measurements
    }
    long long codeOfRep117(float r) const override
    {
        return std::isinf(r) && r > 0 ? lms_code::kNoEcho : lms_code::kWeakOrAmbiguous;
    }
    PhysicalParams physicalDefaults() const override
    {
        PhysicalParams p;
        p.divergence_mrad = 12.0;
        p.noise_floor = 5e-5;  // calibrated: dense plume cores read as obstacles, thin edges as 8189 (docs/sensors.md)
        return p;
    }
    void readOwnKeys(TomlTable& t, SensorConfig& c) const override
    {
        c.lms.resolution_deg = t.num("resolution_deg", c.lms.resolution_deg);
        if (c.lms.resolution_deg != 1.0 && c.lms.resolution_deg != 0.5) t.error("resolution_deg", "must be 1 or 0.5");
        c.lms.range_mode_m = t.num("range_mode_m", c.lms.range_mode_m);
        if (c.lms.range_mode_m != 8.0 && c.lms.range_mode_m != 80.0) t.error("range_mode_m", "must be 8 or 80");
    }
    bool learnsExtensions() const override { return false; }
    bool fitsPhysicalModel() const override { return false; }
    bool fitsPlume() const override { return true; }
};

}  // namespace

const LaserKind& kinds::lms200()
{
    static const Lms200Kind kind;
    return kind;
}

}  // namespace smokescan
