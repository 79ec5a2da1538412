// A lidar's beam pattern from a file (lidar_spec.hpp: readPatternFile), for solid-state or any
// other lidar whose beams are not a spinning head's channels × columns.
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "smokescan/core/error.hpp"
#include "smokescan/io/text_input.hpp"
#include "smokescan/lidar/lidar_spec.hpp"

namespace smokescan {
namespace {

/// The fields of one CSV line, trimmed.
std::vector<std::string> fields(const std::string& line)
{
    std::vector<std::string> out;
    std::string f;
    std::istringstream in(line);
    while (std::getline(in, f, ',')) {
        const size_t a = f.find_first_not_of(" \t\r"), b = f.find_last_not_of(" \t\r");
        out.push_back(a == std::string::npos ? "" : f.substr(a, b - a + 1));
    }
    return out;
}

double number(const std::string& text, const std::string& where, const char* what)
{
    errno = 0;
    char* end = nullptr;
    // Decimal only: strtod would also take hexadecimal ("0x10" as 16).
    if (text.find_first_of("xX") != std::string::npos)
        throw Error(where, std::string(what) + " '" + text + "' is not a decimal number");
    const double v = std::strtod(text.c_str(), &end);
    const bool overflow = errno == ERANGE && std::abs(v) > 1;  // an underflow (1e-400) is its tiny value
    if (text.empty() || *end != '\0' || overflow || !std::isfinite(v))
        throw Error(where, std::string(what) + " '" + text + "' is not a finite number");
    return v;
}

}  // namespace

std::vector<PatternBeam> readPatternFile(const std::string& path, double period_s)
{
    std::string text = readTextInput(path, "pattern file", size_t(256) << 20);
    if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);  // a UTF-8 byte-order mark
    std::istringstream in(text);
    std::vector<PatternBeam> beams;
    std::string line;
    for (long long n = 1; std::getline(in, line); ++n) {
        const std::string where = path + ":" + std::to_string(n);
        const size_t hash = line.find('#');
        if (hash != std::string::npos) line.resize(hash);
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        const std::vector<std::string> f = fields(line);
        if (line.find_last_not_of(" \t\r") == line.rfind(',')) throw Error(where, "ends with a comma (an empty field)");
        if (f.size() != 3 && f.size() != 4)
            throw Error(where, "expected azimuth_deg, elevation_deg, time_s[, channel]");
        if ((long long)beams.size() >= lidar_limits::kBeamsPerFrame)
            throw Error(where, "more than 4,000,000 beams in a frame");
        PatternBeam b;
        const double az = number(f[0], where, "azimuth_deg"), el = number(f[1], where, "elevation_deg");
        b.time_s = number(f[2], where, "time_s");
        if (std::abs(az) > 360) throw Error(where, "azimuth_deg must lie within ±360");
        if (std::abs(el) > 90) throw Error(where, "elevation_deg must lie within ±90");
        if (!(b.time_s >= 0 && b.time_s < period_s))
            throw Error(where, "time_s must lie within the frame [0, " + std::to_string(period_s) + ") s");
        if (!beams.empty() && !(b.time_s > beams.back().time_s))
            throw Error(where, "time_s must increase from line to line (a beam's own firing time)");
        if (f.size() == 4) {
            const double c = number(f[3], where, "channel");
            if (c != std::floor(c) || c < 0 || c > 65535) throw Error(where, "channel must be an integer 0–65535");
            b.channel = int(c);
        }
        b.azimuth_rad = az * M_PI / 180;
        b.elevation_rad = el * M_PI / 180;
        beams.push_back(b);
    }
    if (beams.empty()) throw Error(path, "the pattern file has no beams");
    return beams;
}

}  // namespace smokescan
