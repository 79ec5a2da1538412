#include "smokescan/io/sensor_file.hpp"

#include <fstream>
#include <iomanip>
#include <sstream>

#include "sensor_toml.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/io/text_input.hpp"

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

void readPaperTable(TomlTable t, SensorMount& m)
{
    m.penetration_power = t.positive("penetration_power", m.penetration_power);
    m.local_threshold = t.positive("local_threshold", m.local_threshold);
    t.finish();
}

void applySensorFile(const std::string& path, SensorMount& m)
{
    applySensorText(readTextInput(path, "sensor file"), path, m);
}

void applySensorText(const std::string& text, const std::string& path, SensorMount& m)
{
    const toml::table root = parseToml(text, path);
    TomlTable t(root, path, "");
    const std::string type = t.strReq("type");
    if (type != m.type) t.error("type", "is '" + type + "' but the sensor is a " + m.type);
    m.model = t.str("model", m.model);
    if (m.model != "paper" && m.model != "physical") t.error("model", "must be paper or physical, got '" + m.model + "'");
    if (t.has("paper")) readPaperTable(t.table("paper"), m);
    if (t.has("physical")) readPhysicalTable(t.table("physical"), m.physical);
    t.finish();
    m.sensor_file = path;
}

void writeSensorFile(const std::string& path, const SensorMount& m, const std::string& comment)
{
    std::ostringstream o;
    o << std::setprecision(10);
    o << "# smokescan sensor file (docs/sensors.md)\n";
    if (!comment.empty()) {
        std::istringstream c(comment);
        for (std::string line; std::getline(c, line);) o << "# " << line << "\n";
    }
    o << "type = \"" << m.type << "\"\nmodel = \"" << m.model << "\"\n\n[paper]\n"
      << "penetration_power = " << m.penetration_power << "  # density·m\n"
      << "local_threshold = " << m.local_threshold << "  # density\n\n[physical]\n";
    for (const Field& f : kFields) o << f.name << " = " << m.physical.*f.member << "\n";
    o << "sub_rays = " << m.physical.sub_rays << "\n";
    AtomicFile f(path);
    f.stream() << o.str();
    f.commit();
}

}  // namespace smokescan
