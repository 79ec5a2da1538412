// A lidar spec from its preset file (lidar_spec.hpp's table), and its frame's beam pattern.
#include "smokescan/lidar/lidar_spec.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/io/text_input.hpp"
#include "smokescan/sensors/physical_model.hpp"
#include "toml_reader.hpp"

namespace smokescan {

const std::vector<std::pair<std::string, std::string>>& builtinLidarPresetTable();  // generated

namespace {

constexpr double kDeg = M_PI / 180;
constexpr ReturnMode kModes[] = {ReturnMode::First, ReturnMode::Last, ReturnMode::Strongest, ReturnMode::Dual};

/// The channels' elevations: a list, or [top, bottom, count] spread uniformly.
void readElevations(TomlTable& t, LidarSpec& s)
{
    std::vector<double> deg;
    if (t.has("elevation_deg") == t.has("elevation_uniform_deg"))
        t.error("elevation_deg", "give either elevation_deg or elevation_uniform_deg for a spinning lidar");
    const std::string key = t.has("elevation_deg") ? "elevation_deg" : "elevation_uniform_deg";
    if (t.has("elevation_deg")) {
        deg = t.numbers("elevation_deg", lidar_limits::kChannels);
    } else {
        const std::vector<double> u = t.numbers("elevation_uniform_deg", 3);
        if (u.size() != 3 || u[2] != std::floor(u[2]) || u[2] < 1 || u[2] > lidar_limits::kChannels)
            t.error("elevation_uniform_deg", "must be [top_deg, bottom_deg, count], count 1–512");
        const int n = int(u[2]);
        for (int i = 0; i < n; ++i) deg.push_back(n == 1 ? u[0] : u[0] + (u[1] - u[0]) * i / (n - 1));
    }
    if (deg.empty()) t.error(key, "must list at least one channel");
    for (double d : deg)
        if (std::abs(d) > 90) t.error(key, "must lie within ±90°");
    for (double d : deg) s.elevation_rad.push_back(d * kDeg);
}

/// A per-channel list (`key`), a cycle repeated over the channels (`cycle_key`), or a step per
/// channel (`step_key`), times `unit`; zeros when none is given.
std::vector<double> perChannel(TomlTable& t, size_t n, const std::string& key, const std::string& cycle_key,
                               const std::string& step_key, double unit)
{
    std::vector<double> v(n, 0.0);
    const int given =
        int(t.has(key)) + int(!cycle_key.empty() && t.has(cycle_key)) + int(!step_key.empty() && t.has(step_key));
    if (given > 1)
        t.error(key,
                "give only one of " + key + (cycle_key.empty() ? "" : ", " + cycle_key) +
                    (step_key.empty() ? "" : ", " + step_key));
    if (t.has(key)) {
        const std::vector<double> x = t.numbers(key, lidar_limits::kChannels);
        if (x.size() != n) t.error(key, "must have one value per channel (" + std::to_string(n) + ")");
        for (size_t i = 0; i < n; ++i) v[i] = x[i] * unit;
    } else if (!cycle_key.empty() && t.has(cycle_key)) {
        const std::vector<double> x = t.numbers(cycle_key, lidar_limits::kChannels);
        if (x.empty()) t.error(cycle_key, "must not be empty");
        for (size_t i = 0; i < n; ++i) v[i] = x[i % x.size()] * unit;
    } else if (!step_key.empty() && t.has(step_key)) {
        const double step = t.nonneg(step_key, 0);
        for (size_t i = 0; i < n; ++i) v[i] = double(i) * step * unit;
    }
    return v;
}

void readModes(TomlTable& t, LidarSpec& s)
{
    if (t.has("return_modes")) {
        for (const std::string& m : t.strings("return_modes", 4))
            s.return_modes.push_back(parseReturnMode(m, t.source() + ": return_modes"));
        if (s.return_modes.empty()) t.error("return_modes", "must name at least one mode");
    } else {
        s.return_modes.assign(std::begin(kModes), std::end(kModes));
    }
    const std::string dual = t.str("dual", "strongest_last");
    if (dual != "strongest_last" && dual != "strongest_second")
        t.error("dual", "must be \"strongest_last\" or \"strongest_second\"");
    s.dual_second_strongest = dual == "strongest_second";
    const long long echoes = t.integer("max_echoes", 3);
    if (echoes < 1 || echoes > 8) t.error("max_echoes", "must be 1–8");
    s.max_echoes = int(echoes);
}

/// The receiver: a footprint of five sub-rays, overlap complete by 0.3 m, the noise floor that
/// puts a 10 % Lambertian target's echo at range_at_10pct_m 1.28 σ above the detection threshold:
/// its peak sample alone is detected there 90 % of the time (datasheets quote ranges at ≥ 90 %).
void readReceiver(TomlTable& t, LidarSpec& s)
{
    PhysicalParams& p = s.receiver;
    p.divergence_mrad = t.between("divergence_mrad", 3.0, 0.01, 100);
    p.pulse_fwhm_ns = t.between("pulse_fwhm_ns", 5.0, 0.1, 100);
    p.threshold_snr = t.between("threshold_snr", 6.0, 1, 1000);
    p.overlap_start_m = 0.05;
    p.overlap_full_m = 0.3;
    p.overlap_floor = 0.01;
    p.saturation_power = kInf;
    const double r10 = t.between("range_at_10pct_m", 50, 0.1, 10000);
    p.noise_floor = 0.1 / (r10 * r10) / (p.threshold_snr + 1.2816);
    // Smoke summed onto points a quarter of the pulse's σ apart, two to each of the waveform's
    // samples (receiveEchoes samples it every σ/2).
    p.smoke_cell_m = 0.25 * pulseSigma_m(p);
    p.smoke_bin_m = 2 * p.smoke_cell_m;
}

/// A preset's name: printable on one line (it titles messages, reports and lidar.toml's comment).
std::string readName(TomlTable& t)
{
    const std::string name = t.strReq("name");
    if (name.empty() || name.size() > 64 || printable(name) != name)
        t.error("name", "must be 1–64 printable characters on one line");
    return name;
}

/// [extensions]: its channel and sector tables (lidar_spec.hpp's LidarExtensions table).
void readExtensions(TomlTable t, const LidarSpec& spec, LidarExtensions& e)
{
    const int rings = spec.channels();
    std::vector<TomlTable> channels = t.tables("channel"), sectors = t.tables("sector"), surfaces = t.tables("surface");
    if (channels.size() > size_t(lidar_limits::kChannels)) t.error("channel", "has more tables than channels (512)");
    if (sectors.size() > lidar_limits::kExtensionSectors)
        t.error("sector", "has more than " + std::to_string(lidar_limits::kExtensionSectors) + " tables");
    for (TomlTable& c : channels) {
        LidarChannelExtension x;
        const long long ring = c.integer("ring", -1);
        if (!c.has("ring")) c.error("ring", "is missing: name the channel");
        if (ring < 0 || ring >= rings)
            c.error("ring", "must be a channel of the sensor, 0–" + std::to_string(rings - 1));
        for (const LidarChannelExtension& y : e.channels)
            if (y.ring == ring) c.error("ring", "names a channel already extended (" + std::to_string(ring) + ")");
        x.ring = int(ring);
        x.range_offset_m = c.between("range_offset_m", 0, -1, 1);
        x.dropout = c.between("dropout", 0, 0, 1);
        c.finish("an [[extensions.channel]] table");
        e.channels.push_back(x);
    }
    for (TomlTable& c : sectors) {
        LidarSectorExtension x;
        for (const char* key : {"from_deg", "to_deg", "dropout"})
            if (!c.has(key)) c.error(key, "is missing");
        x.from_deg = c.between("from_deg", 0, -180, 180);
        x.to_deg = c.between("to_deg", 0, -180, 180);
        if (std::remainder(x.from_deg - x.to_deg, 360.0) == 0)
            c.error("to_deg", "is from_deg's azimuth: the sector is empty");
        x.dropout = c.between("dropout", 0, 0, 1);
        c.finish("an [[extensions.sector]] table");
        e.sectors.push_back(x);
    }
    if (surfaces.size() > lidar_limits::kExtensionSurfaces)
        t.error("surface", "has more than " + std::to_string(lidar_limits::kExtensionSurfaces) + " tables");
    for (TomlTable& c : surfaces) {
        LidarSurfaceExtension x;
        for (const char* key : {"name", "reflectance_factor"})
            if (!c.has(key)) c.error(key, "is missing");
        x.name = c.strReq("name");
        if (x.name.size() > lidar_limits::kSurfaceName)
            c.error("name", "must name a surface in at most " + std::to_string(lidar_limits::kSurfaceName) + " bytes");
        for (const LidarSurfaceExtension& y : e.surfaces)
            if (y.name == x.name) c.error("name", "names a surface already extended (" + x.name + ")");
        x.reflectance_factor = c.between("reflectance_factor", 1, 0.01, 10);
        c.finish("an [[extensions.surface]] table");
        e.surfaces.push_back(x);
    }
    t.finish("a lidar's [extensions]");
}

/// A preset that extends another: the base's spec under this one's name, with its extensions.
LidarSpec extendedSpec(TomlTable& t, const std::string& source)
{
    const std::string base = t.strReq("base");
    std::string path = base;
    if (isLidarPresetFile(base)) {
        const std::filesystem::path p(base);
        if (p.is_relative()) path = (std::filesystem::path(source).parent_path() / p).string();
    } else if (!isLidarName(base)) {
        t.error("base", "is neither a built-in preset nor a preset file (*.toml)");
    }
    // One level only: a base that extends another (or itself) is refused before it is read on.
    thread_local bool reading_base = false;
    if (reading_base) t.error("base", "is given in a preset used as a base: a base must be a whole preset");
    struct Reading {  // set while the base is read, also when reading it throws
        Reading() { reading_base = true; }
        ~Reading() { reading_base = false; }
    };
    LidarSpec s;
    {
        const Reading reading;
        s = lidarSpec(path);
    }
    s.name = readName(t);
    s.source = source;
    s.base = path;
    if (t.has("extensions")) readExtensions(t.table("extensions"), s, s.extensions);
    t.finish("a preset that extends another (base): only name and [extensions] may be given");
    return s;
}

}  // namespace

bool LidarSectorExtension::contains(double azimuth_rad) const
{
    double deg = std::fmod(azimuth_rad * 180 / M_PI + 180, 360.0);
    deg = (deg < 0 ? deg + 360 : deg) - 180;
    return from_deg <= to_deg ? deg >= from_deg && deg < to_deg : deg >= from_deg || deg < to_deg;
}

double LidarExtensions::dropout(int ring, double azimuth_rad) const
{
    double keep = 1;
    for (const LidarChannelExtension& c : channels)
        if (c.ring == ring) keep *= 1 - c.dropout;
    for (const LidarSectorExtension& s : sectors)
        if (s.contains(azimuth_rad)) keep *= 1 - s.dropout;
    return 1 - keep;
}

double LidarExtensions::rangeOffset_m(int ring) const
{
    for (const LidarChannelExtension& c : channels)
        if (c.ring == ring) return c.range_offset_m;
    return 0;
}

std::string extendedPresetName(const std::string& name)
{
    constexpr const char* kSuffix = "-extended";
    if (name.size() >= 9 && name.compare(name.size() - 9, 9, kSuffix) == 0) return name;
    // Cut on a UTF-8 character's boundary, so that the name stays printable.
    size_t keep = std::min(name.size(), size_t(64 - 9));
    while (keep > 0 && keep < name.size() && (static_cast<unsigned char>(name[keep]) & 0xC0) == 0x80) --keep;
    return name.substr(0, keep) + kSuffix;
}

std::string lidarExtensionsToml(const LidarExtensions& e)
{
    const auto num = shortest;  // reads back as the value written
    std::string o;
    for (const LidarChannelExtension& c : e.channels)
        o += "\n[[extensions.channel]]\nring = " + std::to_string(c.ring) +
            "\nrange_offset_m = " + num(c.range_offset_m) + "\ndropout = " + num(c.dropout) + "\n";
    for (const LidarSectorExtension& x : e.sectors)
        o += "\n[[extensions.sector]]\nfrom_deg = " + num(x.from_deg) + "\nto_deg = " + num(x.to_deg) +
            "\ndropout = " + num(x.dropout) + "\n";
    for (const LidarSurfaceExtension& x : e.surfaces)
        o += "\n[[extensions.surface]]\nname = " + tomlQuoted(x.name) +
            "\nreflectance_factor = " + num(x.reflectance_factor) + "\n";
    return o;
}

const char* returnModeName(ReturnMode m)
{
    switch (m) {
    case ReturnMode::First:
        return "first";
    case ReturnMode::Last:
        return "last";
    case ReturnMode::Strongest:
        return "strongest";
    case ReturnMode::Dual:
        return "dual";
    }
    return "?";
}

ReturnMode parseReturnMode(const std::string& name, const std::string& where)
{
    for (ReturnMode m : kModes)
        if (name == returnModeName(m)) return m;
    throw Error(where, "unknown return mode '" + name + "' (first, last, strongest or dual)");
}

bool LidarSpec::offers(ReturnMode m) const
{
    return std::find(return_modes.begin(), return_modes.end(), m) != return_modes.end();
}

LidarSpec parseLidarSpec(const std::string& text, const std::string& source)
{
    const toml::table root = parseToml(text, source);
    TomlTable t(root, source, "");
    if (t.has("base")) return extendedSpec(t, source);
    LidarSpec s;
    s.source = source;
    s.name = readName(t);
    const std::string pattern = t.strReq("pattern");
    if (pattern != "spinning" && pattern != "file") t.error("pattern", "must be \"spinning\" or \"file\"");
    s.pattern = pattern == "file" ? PatternKind::File : PatternKind::Spinning;
    s.wavelength_nm = t.between("wavelength_nm", 905, 200, 2000);
    s.rate_hz = t.between("rate_hz", 10, 0.01, lidar_limits::kRateHz);
    s.rates_hz = t.has("rates_hz") ? t.numbers("rates_hz", 64) : std::vector<double>{s.rate_hz};
    for (double r : s.rates_hz)
        if (!(r >= 0.01 && r <= lidar_limits::kRateHz)) t.error("rates_hz", "must hold rates in [0.01, 100] Hz");
    if (std::find(s.rates_hz.begin(), s.rates_hz.end(), s.rate_hz) == s.rates_hz.end())
        t.error("rate_hz", "must be one of rates_hz");
    s.range_min_m = t.between("range_min_m", 0.5, 0, 1e4);
    s.range_max_m = t.between("range_max_m", 100, 0.1, 1e4);
    if (!(s.range_max_m > s.range_min_m)) t.error("range_max_m", "must exceed range_min_m");
    s.range_sigma_m = t.between("range_sigma_m", 0.02, 0, 10);
    readReceiver(t, s);
    readModes(t, s);
    if (s.pattern == PatternKind::File) {
        const std::string file = t.strReq("pattern_file");
        if (file.empty()) t.error("pattern_file", "is empty: name the CSV of the beams");
        const std::filesystem::path base = std::filesystem::path(source).parent_path();
        s.pattern_file = (base / file).string();
        s.file_beams = readPatternFile(s.pattern_file, 1 / s.rate_hz);
        for (const PatternBeam& b : s.file_beams) s.file_channels = std::max(s.file_channels, b.channel + 1);
        s.columns = 1;
    } else {
        const std::string spin = t.str("spin", "cw");
        if (spin != "cw" && spin != "ccw") t.error("spin", "must be \"cw\" or \"ccw\"");
        s.clockwise = spin == "cw";
        readElevations(t, s);
        const size_t n = s.elevation_rad.size();
        s.azimuth_offset_rad = perChannel(t, n, "azimuth_offset_deg", "azimuth_offset_cycle_deg", "", kDeg);
        s.fire_offset_s = perChannel(t, n, "fire_offset_us", "", "fire_offset_step_us", 1e-6);
        if (t.has("firing_cycle_us")) {
            s.firing_cycle_s = t.between("firing_cycle_us", 50, 0.01, 1e6) * 1e-6;
            if (t.has("columns")) t.error("columns", "is set by firing_cycle_us for this sensor");
        } else {
            const long long columns = t.integer("columns", 1024);
            if (columns < 1 || columns > lidar_limits::kColumns) t.error("columns", "must be 1–8192");
            s.columns = int(columns);
            if (t.has("columns_allowed")) {
                for (double x : t.numbers("columns_allowed", 64)) {
                    if (!(x >= 1 && x <= lidar_limits::kColumns && x == std::floor(x)))
                        t.error("columns_allowed", "must hold whole column counts 1–8192");
                    s.columns_allowed.push_back(int(x));
                }
                if (std::find(s.columns_allowed.begin(), s.columns_allowed.end(), s.columns) == s.columns_allowed.end())
                    t.error("columns", "must be one of columns_allowed");
            } else {
                s.columns_allowed = {s.columns};
            }
        }
        for (double a : s.azimuth_offset_rad)
            if (std::abs(a) > 2 * M_PI) t.error("azimuth_offset_deg", "must lie within ±360°");
        for (double f : s.fire_offset_s)
            if (f < 0) t.error("fire_offset_us", "must not be negative (a channel fires within its column)");
        s.max_column_rate_hz = t.nonneg("max_column_rate_hz", 0);
        configureLidar(s, s.rate_hz, 0, source, source);
    }
    if (t.has("extensions"))
        t.error("extensions",
                "belongs in a preset that extends this one (base = \"" + source +
                    "\"): a whole preset is the sensor's datasheet");
    t.finish("a lidar preset");
    return s;
}

void configureLidar(LidarSpec& s, double rate_hz, int columns, const std::string& rate_where,
                    const std::string& columns_where)
{
    auto fmtList = [](const auto& v) {
        std::string out;
        for (const auto& x : v) {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%.12g", double(x));
            out += (out.empty() ? "" : ", ") + std::string(buf);
        }
        return out;
    };
    // A combination the sensor cannot fire is named by what was set (both when both were).
    const std::string both = rate_where == columns_where || columns <= 0 ? rate_where
        : rate_hz <= 0                                                   ? columns_where
                                                                         : rate_where + " and " + columns_where;
    if (rate_hz > 0) {
        if (std::find(s.rates_hz.begin(), s.rates_hz.end(), rate_hz) == s.rates_hz.end())
            throw Error(rate_where,
                        "the " + s.name + " spins at " + fmtList(s.rates_hz) + " Hz, not " +
                            fmtList(std::vector<double>{rate_hz}));
        s.rate_hz = rate_hz;
    }
    if (s.pattern == PatternKind::File) {
        if (columns > 0)
            throw Error(columns_where, "the " + s.name + " fires a pattern file: it has no columns to set");
        if (!s.file_beams.empty() && !(s.file_beams.back().time_s < 1 / s.rate_hz))
            throw Error(rate_where,
                        "the " + s.name + "'s pattern fires until " +
                            fmtList(std::vector<double>{s.file_beams.back().time_s}) + " s, beyond a frame of " +
                            fmtList(std::vector<double>{1 / s.rate_hz}) + " s at " +
                            fmtList(std::vector<double>{s.rate_hz}) + " Hz");
        return;
    }
    if (s.firing_cycle_s > 0) {
        const int follow = int(std::floor(1 / (s.rate_hz * s.firing_cycle_s) + 1e-9));
        if (columns > 0 && columns != follow)
            throw Error(columns_where,
                        "the " + s.name +
                            "'s columns follow from its rate (a column each firing cycle): " + std::to_string(follow) +
                            " at " + fmtList(std::vector<double>{s.rate_hz}) + " Hz, not " + std::to_string(columns));
        s.columns = follow;
    } else if (columns > 0) {
        if (std::find(s.columns_allowed.begin(), s.columns_allowed.end(), columns) == s.columns_allowed.end())
            throw Error(
                columns_where,
                "the " + s.name + " offers " + fmtList(s.columns_allowed) + " columns, not " + std::to_string(columns));
        s.columns = columns;
    }
    if (s.columns < 1 || s.columns > lidar_limits::kColumns)
        throw Error(both, "the " + s.name + " would fire " + std::to_string(s.columns) + " columns a turn (1–8192)");
    if (s.max_column_rate_hz > 0 && s.columns * s.rate_hz > s.max_column_rate_hz * (1 + 1e-12))
        throw Error(both,
                    "the " + s.name + " fires at most " + fmtList(std::vector<double>{s.max_column_rate_hz}) +
                        " columns a second: " + std::to_string(s.columns) + " columns at " +
                        fmtList(std::vector<double>{s.rate_hz}) + " Hz is not one of its modes");
    if ((long long)s.columns * s.channels() > lidar_limits::kBeamsPerFrame)
        throw Error(both, "the " + s.name + " would fire more than 4,000,000 beams a frame");
    // Every channel fires within its column, or columns would overlap.
    const double column_s = s.firing_cycle_s > 0 ? s.firing_cycle_s : 1 / (s.rate_hz * s.columns);
    for (double f : s.fire_offset_s)
        if (!(f < column_s))
            throw Error(both,
                        "the " + s.name + "'s channels fire up to " + fmtList(std::vector<double>{f * 1e6}) +
                            " us into a column of " + fmtList(std::vector<double>{column_s * 1e6}) + " us");
}

int frameColumns(const LidarSpec& s) { return s.pattern == PatternKind::File ? 1 : s.columns; }

std::vector<PatternBeam> framePattern(const LidarSpec& s)
{
    if (s.pattern == PatternKind::File) return s.file_beams;
    std::vector<PatternBeam> out;
    const int C = s.columns, N = s.channels();
    out.reserve(size_t(C) * size_t(N));
    const double period = 1 / s.rate_hz, column_s = s.firing_cycle_s > 0 ? s.firing_cycle_s : period / C;
    const double turn = (s.clockwise ? -2 : 2) * M_PI / period;  // azimuth rate [rad/s]
    for (int c = 0; c < C; ++c)
        for (int ch = 0; ch < N; ++ch) {
            PatternBeam b;
            b.time_s = c * column_s + s.fire_offset_s[size_t(ch)];
            // The head turns on between a column's firings: each beam's azimuth is the head's at its own time.
            b.azimuth_rad = std::remainder(turn * b.time_s + s.azimuth_offset_rad[size_t(ch)], 2 * M_PI);
            b.elevation_rad = s.elevation_rad[size_t(ch)];
            b.channel = ch;
            out.push_back(b);
        }
    return out;
}

std::vector<std::string> lidarPresetNames()
{
    std::vector<std::string> names;
    for (const auto& [name, text] : builtinLidarPresetTable()) names.push_back(name);
    return names;
}

bool isLidarName(const std::string& name)
{
    for (const auto& [n, text] : builtinLidarPresetTable())
        if (n == name) return true;
    return isLidarPresetFile(name);
}

bool isLidarPresetFile(const std::string& name)
{
    return name.size() > 5 && name.compare(name.size() - 5, 5, ".toml") == 0;
}

LidarSpec lidarSpec(const std::string& name)
{
    for (const auto& [n, text] : builtinLidarPresetTable())
        if (n == name) return parseLidarSpec(text, "preset " + n);
    if (isLidarPresetFile(name))
        return parseLidarSpec(readTextInput(name, "lidar preset", limits::kTomlInputBytes), name);
    std::string names;
    for (const std::string& n : lidarPresetNames()) names += (names.empty() ? "" : ", ") + n;
    throw Error("--sensor", "no lidar preset '" + name + "' (presets: " + names + "; or a preset file *.toml)");
}

}  // namespace smokescan
