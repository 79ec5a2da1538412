#include "smokescan/sensors/sensor_file.hpp"

#include <iomanip>
#include <sstream>

#include "sensor_tables.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/io/text_input.hpp"

namespace smokescan {

void applySensorFile(const std::string& path, SensorConfig& c)
{
    applySensorText(readTextInput(path, "sensor file"), path, c);
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
    if (t.has("physical")) readPhysicalTable(t.table("physical"), c.physical);
    if (t.has("extensions")) {
        readExtensionsTable(t.table("extensions"), c.extensions);
        if (c.extensions.changesBeams() && c.type != SensorType::Urg04lx)
            t.error("extensions",
                    "extend the urg04lx's models; this file's sensor is an " + std::string(sensorTypeName(c.type)));
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
    writePhysicalTable(o, c.physical);
    if (c.extensions.changesBeams() || c.extensions.clock_offset_s != 0) {
        o << "\n";
        writeExtensionsTable(o, c.extensions);
    }
    AtomicFile f(path);
    f.stream() << o.str();
    f.commit();
}

}  // namespace smokescan
