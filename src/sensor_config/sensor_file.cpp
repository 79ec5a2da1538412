#include "smokescan/sensor_config/sensor_file.hpp"

#include <iomanip>
#include <sstream>

#include "sensor_tables.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/io/text_input.hpp"
#include "smokescan/sensor_config/laser_kind.hpp"

namespace smokescan {

void applySensorFile(const std::string& path, SensorConfig& c)
{
    applySensorText(readTextInput(path, "sensor file", limits::kTomlInputBytes), path, c);
}

void applySensorText(const std::string& text, const std::string& path, SensorConfig& c)
{
    const toml::table root = parseToml(text, path);
    TomlTable t(root, path, "");
    const std::string type = t.strReq("type");
    if (type != sensorTypeName(c.type))
        t.error("type", "is '" + type + "' but the sensor is a " + sensorTypeName(c.type));
    c.model = readSensorModel(t, "model", c.model);
    if (t.has("paper")) readPaperTable(t.table("paper"), c.paper);
    if (t.has("physical")) readPhysicalTable(t.table("physical"), c.physical, c.type);
    if (t.has("extensions")) {
        readExtensionsTable(t.table("extensions"), c.extensions);
        if (c.extensions.changesBeams() && !laserKind(c.type).learnsExtensions())
            t.error("extensions",
                    "change the beams, but this file's sensor is " + laserKind(c.type).withArticle() +
                        ", whose models take none");
    }
    t.finish();
    c.sensor_file = path;
}

void writeSensorFile(const std::string& path, const SensorConfig& c, const std::string& comment)
{
    std::ostringstream o;
    o << std::setprecision(10);
    o << "# smokescan sensor file (docs/sensors.md)\n";
    if (!comment.empty()) {
        std::istringstream lines(comment);
        for (std::string line; std::getline(lines, line);) o << "# " << line << "\n";
    }
    o << "type = \"" << sensorTypeName(c.type) << "\"\nmodel = \"" << sensorModelName(c.model) << "\"\n\n[paper]\n";
    writePaperTable(o, c.paper);
    o << "\n[physical]\n";
    writePhysicalTable(o, c.physical, c.type);
    if (c.extensions.changesBeams() || c.extensions.clock_offset_s != 0) {
        o << "\n";
        writeExtensionsTable(o, c.extensions);
    }
    AtomicFile f(path);
    f.stream() << o.str();
    f.commit();
}

OmniSensorFile readOmniSensorFile(const std::string& path)
{
    const toml::table root = parseToml(readTextInput(path, "sensor file", limits::kTomlInputBytes), path);
    TomlTable t(root, path, "");
    const std::string type = t.strReq("type");
    if (type != "omnicam") t.error("type", "is '" + type + "' but an omnicam's file is needed (type = \"omnicam\")");
    OmniSensorFile f;
    f.path = path;
    f.camera = t.str("camera", "");
    f.tolerance_m = t.positive("tolerance_m", f.tolerance_m);
    f.max_range_m = t.positive("max_range_m", f.max_range_m);
    f.floor_z_m = t.num("floor_z_m", f.floor_z_m);
    if (!t.has("paper")) t.error("paper", "is missing: the omnicam's onset is its penetration_power");
    TomlTable paper = t.table("paper");
    f.penetration_power = paper.positive("penetration_power", 0);
    if (f.penetration_power < 1e-9 || f.penetration_power > 1e3)
        paper.error("penetration_power", "must lie in 1e-9…1e3 density·m (the omnicam's onset)");
    paper.finish();
    if (t.has("extensions")) readExtensionsTable(t.table("extensions"), f.extensions);
    t.finish();
    return f;
}

void writeOmniSensorFile(const std::string& path, const OmniSensorFile& f, const std::string& comment)
{
    std::ostringstream o;
    o << std::setprecision(10);
    o << "# smokescan omnicam sensor file (docs/omnicam.md); `smokescan scan` simulates lasers and refuses it\n";
    std::istringstream lines(comment);
    for (std::string line; std::getline(lines, line);) o << "# " << line << "\n";
    o << "type = \"omnicam\"\ncamera = " << tomlQuoted(f.camera) << "\ntolerance_m = " << f.tolerance_m
      << "  # a reading this far off its truth failed [m]\nmax_range_m = " << f.max_range_m
      << "  # the rangefinder's maximum range [m]\nfloor_z_m = " << f.floor_z_m
      << "  # the floor's height [m]\n\n[paper]\npenetration_power = " << f.penetration_power
      << "  # the column along the line of sight at which half its readings fail [density·m]\n";
    if (f.extensions.changesBeams() || f.extensions.clock_offset_s != 0) {
        o << "\n";
        writeExtensionsTable(o, f.extensions);
    }
    AtomicFile file(path);
    file.stream() << o.str();
    file.commit();
}

}  // namespace smokescan
