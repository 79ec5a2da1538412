#include "sensor_tables.hpp"

#include <cmath>

#include "smokescan/core/format.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/sensor_config/laser_kind.hpp"

namespace smokescan {
namespace {

// One table of every PhysicalParams field: name, member, bounds, and the receiver it belongs
// to (an AMCW phase receiver or a pulse receiver, the kind's; both: the optics and noise).
// Reading and writing share it; a key of the other receiver is refused.
enum class Owner { Both, Amcw, Pulsed };
struct Field {
    const char* name;
    double PhysicalParams::*member;
    double lo, hi;  ///< inclusive; every field is > 0
    Owner owner;
};
const Field kFields[] = {
    {"divergence_mrad", &PhysicalParams::divergence_mrad, 1e-3, 1e3, Owner::Both},
    {"overlap_start_m", &PhysicalParams::overlap_start_m, 1e-6, 1e3, Owner::Both},
    {"overlap_full_m", &PhysicalParams::overlap_full_m, 1e-6, 1e3, Owner::Both},
    {"overlap_floor", &PhysicalParams::overlap_floor, 1e-12, 1, Owner::Both},
    {"window_m", &PhysicalParams::window_m, 1e-6, 10, Owner::Both},
    {"noise_floor", &PhysicalParams::noise_floor, 1e-15, 1e3, Owner::Both},
    {"saturation_power", &PhysicalParams::saturation_power, 1e-12, 1e9, Owner::Both},
    {"snr_min", &PhysicalParams::snr_min, 1e-3, 1e6, Owner::Amcw},
    {"mod_freq_lo_hz", &PhysicalParams::mod_freq_lo_hz, 1e3, 1e11, Owner::Amcw},
    {"mod_freq_hi_hz", &PhysicalParams::mod_freq_hi_hz, 1e3, 1e11, Owner::Amcw},
    {"two_wave_tolerance", &PhysicalParams::two_wave_tolerance, 1e-6, 0.999, Owner::Amcw},
    {"pulse_fwhm_ns", &PhysicalParams::pulse_fwhm_ns, 1e-3, 1e4, Owner::Pulsed},
    {"threshold_snr", &PhysicalParams::threshold_snr, 1e-3, 1e6, Owner::Pulsed},
    {"valid_snr", &PhysicalParams::valid_snr, 1e-3, 1e6, Owner::Pulsed},
    {"max_echo_width", &PhysicalParams::max_echo_width, 1e-3, 1e6, Owner::Pulsed},
};

bool has(SensorType type, const Field& f)
{
    const bool amcw = laserKind(type).receiver() == Receiver::Amcw;
    return f.owner == Owner::Both || f.owner == (amcw ? Owner::Amcw : Owner::Pulsed);
}

}  // namespace

void readPhysicalTable(TomlTable t, PhysicalParams& p, SensorType type)
{
    for (const Field& f : kFields)
        if (has(type, f)) p.*f.member = t.between(f.name, p.*f.member, f.lo, f.hi);
    const long long n = t.integer("sub_rays", p.sub_rays);
    if (n < 1 || n > 64) t.error("sub_rays", "must lie in 1…64");
    p.sub_rays = int(n);
    p.overlap_blur_m = t.nonneg("overlap_blur_m", p.overlap_blur_m);
    if (p.overlap_blur_m > p.overlap_start_m) t.error("overlap_blur_m", "must not exceed overlap_start_m");
    if (p.overlap_full_m < p.overlap_start_m) t.error("overlap_full_m", "must not be below overlap_start_m");
    const LaserKind& kind = laserKind(type);
    if (kind.receiver() == Receiver::Amcw && p.mod_freq_hi_hz <= p.mod_freq_lo_hz)
        t.error("mod_freq_hi_hz", "must exceed mod_freq_lo_hz");
    if (kind.receiver() == Receiver::Pulsed && p.valid_snr < p.threshold_snr)
        t.error("valid_snr", "must not be below threshold_snr");
    t.finish("the physical model of " + kind.withArticle());
}

void writePhysicalTable(std::ostream& o, const PhysicalParams& p, SensorType type)
{
    for (const Field& f : kFields)
        if (has(type, f)) o << f.name << " = " << shortest(p.*f.member) << "\n";
    o << "sub_rays = " << p.sub_rays << "\n";
    if (p.overlap_blur_m > 0) o << "overlap_blur_m = " << shortest(p.overlap_blur_m) << "\n";
}

void readPaperTable(TomlTable t, PaperModelConfig& p)
{
    p.penetration_power = t.between("penetration_power", p.penetration_power, 1e-9, 1e3);
    p.local_threshold = t.between("local_threshold", p.local_threshold, 1e-9, limits::kDensity);
    t.finish();
}

void writePaperTable(std::ostream& o, const PaperModelConfig& p)
{
    o << "penetration_power = " << shortest(p.penetration_power) << "  # density·m\n"
      << "local_threshold = " << shortest(p.local_threshold) << "  # density\n";
}

void readExtensionsTable(TomlTable t, ModelExtensions& e)
{
    namespace eb = extension_bounds;  // shared with the diagnosis (diagnose/causes.cpp)
    e = ModelExtensions{};  // a learned model is one whole: the section replaces any earlier one
    auto read = [](TomlTable& tt, const char* key, double def, ExtensionBound bound) {
        return tt.between(key, def, bound.lo, bound.hi);
    };
    auto required = [&read](TomlTable& tt, const char* key, ExtensionBound bound) {
        tt.numReq(key);  // names a missing key
        return read(tt, key, 0.0, bound);
    };
    e.clock_offset_s = read(t, "clock_offset_s", e.clock_offset_s, eb::kClockOffset_s);
    e.threshold_width = read(t, "threshold_width", e.threshold_width, eb::kThresholdWidth);
    e.range_noise_growth_m = read(t, "range_noise_growth_m", e.range_noise_growth_m, eb::kNoiseGrowth_m);
    e.smoke_obstacle_return = read(t, "smoke_obstacle_return", e.smoke_obstacle_return, eb::kShare);
    e.hysteresis = read(t, "hysteresis", e.hysteresis, eb::kLnFactor);
    for (TomlTable s : t.tables("surface")) {
        const std::string name = s.strReq("name");
        if (name.empty()) s.error("name", "must not be empty");
        if (e.surfaces.count(name)) s.error("name", "'" + name + "' appears twice");
        SurfaceExtension x;
        x.threshold_factor = read(s, "threshold_factor", 0.0, eb::kLnFactor);
        x.range_bias = read(s, "range_bias", 0.0, eb::kRangeBias);
        s.finish();
        e.surfaces[name] = x;
    }
    for (TomlTable s : t.tables("sector")) {
        SectorExtension x;
        x.from_deg = required(s, "from_deg", eb::kSectorAngle_deg);
        x.to_deg = required(s, "to_deg", eb::kSectorAngle_deg);
        x.dropout = required(s, "dropout", eb::kShare);
        if (!(x.to_deg >= x.from_deg)) s.error("to_deg", "must not be below from_deg");
        s.finish();
        e.sectors.push_back(x);
    }
    t.finish();
}

void writeExtensionsTable(std::ostream& o, const ModelExtensions& e)
{
    o << "[extensions]  # learned by smokescan diagnose (docs/diagnosis.md)\n"
      << "clock_offset_s = " << shortest(e.clock_offset_s) << "  # camera clock - laser clock [s]\n"
      << "threshold_width = " << shortest(e.threshold_width) << "  # the onset's spread [ln column]\n"
      << "range_noise_growth_m = " << shortest(e.range_noise_growth_m) << "  # range noise per density·m of smoke [m]\n"
      << "smoke_obstacle_return = " << shortest(e.smoke_obstacle_return)
      << "  # share of smoke-stopped beams reading short\n"
      << "hysteresis = " << shortest(e.hysteresis) << "  # ln P(falling) - ln P(rising)\n";
    for (const auto& [name, x] : e.surfaces)
        o << "\n[[extensions.surface]]\nname = " << tomlQuoted(name)
          << "\nthreshold_factor = " << shortest(x.threshold_factor)
          << "  # ln(P_surface / P)\nrange_bias = " << shortest(x.range_bias)
          << "  # reads L(1 + bias·column) [1/(density·m)]\n";
    for (const SectorExtension& x : e.sectors)
        o << "\n[[extensions.sector]]\nfrom_deg = " << shortest(x.from_deg) << "\nto_deg = " << shortest(x.to_deg)
          << "\ndropout = " << shortest(x.dropout) << "  # probability that a beam in the sector fails\n";
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
    c.paper.penetration_power = t.between("penetration_power", c.paper.penetration_power, 1e-9, 1e3);
    c.paper.local_threshold = t.between("local_threshold", c.paper.local_threshold, 1e-9, limits::kDensity);
    if (t.has("physical")) readPhysicalTable(t.table("physical"), c.physical, c.type);
    laserKind(c.type).readOwnKeys(t, c);  // e.g. the LMS200's resolution and range mode
}

}  // namespace smokescan
