// The Hokuyo URG-04LX as a kind (sensor_config/laser_kind.hpp): AMCW phase ranging at 785 nm.
#include "smokescan/sensor_config/urg04lx.hpp"

#include <cmath>

#include "kinds.hpp"
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
    s.first_range_value = urg_code::kFirstRange;  // every value below is an error code
    s.sigma_near_m = 0.005;
    s.near_limit_m = 1.0;
    s.sigma_rel = 0.005;
    return s;
}

namespace {

class Urg04lxKind final : public LaserKind {
public:
    SensorType type() const override { return SensorType::Urg04lx; }
    const char* name() const override { return "urg04lx"; }
    const char* article() const override { return "an"; }  // "you-ar-gee", "el-em-ess"
    Receiver receiver() const override { return Receiver::Amcw; }
    LrfSpec spec(const SensorConfig&) const override { return urg04lx(); }
    std::string errorValueSummary() const override { return "values below 20 (0 = no return)"; }
    float rep117(long long v) const override
    {
        // No return and too weak a signal: nothing measured in range. The two waves' disagreement
        // and a saturated receiver: a measurement that failed.
        return v == urg_code::kNoReturn || v == urg_code::kLowIntensity ? INFINITY : NAN;
    }
    long long codeOfRep117(float r) const override
    {
        return std::isinf(r) && r > 0 ? urg_code::kNoReturn : urg_code::kTwoWaveDifference;
    }
    PhysicalParams physicalDefaults() const override
    {
        PhysicalParams p;
        p.overlap_start_m = 1.5;
        p.overlap_full_m = 3.0;
        p.overlap_floor = 0.03;
        // Calibrated, both (docs/sensors.md): the amplitude threshold snr_min·noise_floor puts the
        // bocas blue paper's onset at the paper's 0.007 density·m; the noise alone sets how sharp
        // the onset is, and the paper saw no errors below it (5.4e-4 with snr_min 8 gave two-wave
        // errors from 0.004 density·m, in the first puff).
        p.snr_min = 25;
        p.noise_floor = 1.728e-4;
        return p;
    }
    bool learnsExtensions() const override { return true; }
    bool fitsPhysicalModel() const override { return true; }
    bool fitsPlume() const override { return false; }
};

}  // namespace

const LaserKind& kinds::urg04lx()
{
    static const Urg04lxKind kind;
    return kind;
}

}  // namespace smokescan
