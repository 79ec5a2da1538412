#include "sensor_tables.hpp"

namespace smokescan {
namespace {

// One table of every PhysicalParams field: name, member. Reading and writing share it.
struct Field {
    const char* name;
    double PhysicalParams::*member;
};
const Field kFields[] = {
    {"divergence_mrad", &PhysicalParams::divergence_mrad},
    {"overlap_start_m", &PhysicalParams::overlap_start_m},
    {"overlap_full_m", &PhysicalParams::overlap_full_m},
    {"overlap_floor", &PhysicalParams::overlap_floor},
    {"window_m", &PhysicalParams::window_m},
    {"noise_floor", &PhysicalParams::noise_floor},
    {"saturation_power", &PhysicalParams::saturation_power},
    {"snr_min", &PhysicalParams::snr_min},
    {"mod_freq_lo_hz", &PhysicalParams::mod_freq_lo_hz},
    {"mod_freq_hi_hz", &PhysicalParams::mod_freq_hi_hz},
    {"two_wave_tolerance", &PhysicalParams::two_wave_tolerance},
    {"pulse_fwhm_ns", &PhysicalParams::pulse_fwhm_ns},
    {"threshold_snr", &PhysicalParams::threshold_snr},
    {"valid_snr", &PhysicalParams::valid_snr},
    {"max_echo_width", &PhysicalParams::max_echo_width},
};

}  // namespace

void readPhysicalTable(TomlTable t, PhysicalParams& p)
{
    for (const Field& f : kFields) p.*f.member = t.positive(f.name, p.*f.member);
    const long long n = t.integer("sub_rays", p.sub_rays);
    if (n < 1 || n > 64) t.error("sub_rays", "must lie in 1…64");
    p.sub_rays = int(n);
    if (p.overlap_full_m < p.overlap_start_m) t.error("overlap_full_m", "must not be below overlap_start_m");
    if (p.mod_freq_hi_hz <= p.mod_freq_lo_hz) t.error("mod_freq_hi_hz", "must exceed mod_freq_lo_hz");
    if (p.valid_snr < p.threshold_snr) t.error("valid_snr", "must not be below threshold_snr");
    if (p.overlap_floor > 1) t.error("overlap_floor", "must be <= 1");
    if (p.two_wave_tolerance >= 1) t.error("two_wave_tolerance", "must be < 1");
    t.finish();
}

void writePhysicalTable(std::ostream& o, const PhysicalParams& p)
{
    for (const Field& f : kFields) o << f.name << " = " << p.*f.member << "\n";
    o << "sub_rays = " << p.sub_rays << "\n";
}

void readPaperTable(TomlTable t, PaperModelConfig& p)
{
    p.penetration_power = t.positive("penetration_power", p.penetration_power);
    p.local_threshold = t.positive("local_threshold", p.local_threshold);
    t.finish();
}

void writePaperTable(std::ostream& o, const PaperModelConfig& p)
{
    o << "penetration_power = " << p.penetration_power << "  # density·m\n"
      << "local_threshold = " << p.local_threshold << "  # density\n";
}

SensorModel readSensorModel(TomlTable& t, const char* key, SensorModel def)
{
    if (!t.has(key)) return def;
    const std::string name = t.strReq(key);
    const auto m = parseSensorModel(name);
    if (!m) t.error(key, std::string("must be ") + sensorModelNames() + ", got '" + name + "'");
    return *m;
}

void readSceneSensorKeys(TomlTable& t, SensorConfig& c)
{
    c.model = readSensorModel(t, "model", c.model);
    c.paper.penetration_power = t.positive("penetration_power", c.paper.penetration_power);
    c.paper.local_threshold = t.positive("local_threshold", c.paper.local_threshold);
    if (t.has("physical")) readPhysicalTable(t.table("physical"), c.physical);
    c.lms.resolution_deg = t.num("resolution_deg", c.lms.resolution_deg);
    if (c.lms.resolution_deg != 1.0 && c.lms.resolution_deg != 0.5) t.error("resolution_deg", "must be 1 or 0.5");
    c.lms.range_mode_m = t.num("range_mode_m", c.lms.range_mode_m);
    if (c.lms.range_mode_m != 8.0 && c.lms.range_mode_m != 80.0) t.error("range_mode_m", "must be 8 or 80");
}

}  // namespace smokescan
