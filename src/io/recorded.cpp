#include "smokescan/io/recorded.hpp"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/io/text_input.hpp"

namespace smokescan {
namespace {

bool blankOrComment(const std::string& line)
{
    const size_t first = line.find_first_not_of(" \t\r");
    return first == std::string::npos || line[first] == '#';
}

/// A number field, or why not ("" on success).
std::string parseField(const std::string& tok, size_t index, double& v)
{
    char* end = nullptr;
    v = std::strtod(tok.c_str(), &end);
    const std::string field = "field " + std::to_string(index + 1);
    if (tok.empty()) return field + " is empty";
    if (end == tok.c_str() || *end != '\0') return field + " is not a number: '" + tok + "'";
    if (!std::isfinite(v)) return field + " is not finite";
    return "";
}

/// Either throws (strict) or records the line as skipped.
void problem(const std::string& where, const std::string& what, bool lenient, std::vector<SkippedLine>& skipped)
{
    if (!lenient) throw Error(where, what);
    skipped.push_back({where, what});
}

std::vector<std::string> splitCsv(const std::string& line)
{
    std::vector<std::string> out;
    std::stringstream ss(line);
    std::string tok;
    while (std::getline(ss, tok, ',')) {
        const size_t a = tok.find_first_not_of(" \t\r"), b = tok.find_last_not_of(" \t\r");
        out.push_back(a == std::string::npos ? "" : tok.substr(a, b - a + 1));
    }
    if (!line.empty() && line.back() == ',') out.push_back("");
    return out;
}

/// Why a scan's (angle, range) pairs cannot be a laser's, or "": an angle beyond ±2π rad, a
/// negative range, or one beyond 1 km (in the log's unit).
std::string implausibleBeam(const std::vector<double>& f, double unit_m)
{
    constexpr double kTwoPi = 6.283185307179586, kMaxRange_m = 1000.0;
    for (size_t i = 1; i + 1 < f.size(); i += 2) {
        const std::string beam = "beam " + std::to_string(i / 2);
        if (std::abs(f[i]) > kTwoPi + 1e-9) return beam + ": angle " + std::to_string(f[i]) + " rad is beyond ±2π";
        if (f[i + 1] < 0) return beam + ": range " + std::to_string(f[i + 1]) + " is negative";
        if (f[i + 1] * unit_m > kMaxRange_m)
            return beam + ": range " + std::to_string(f[i + 1] * unit_m) + " m is beyond 1 km (wrong --unit?)";
    }
    return "";
}

bool endsWith(const std::string& s, const std::string& suffix)
{
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

double parseRangeUnit(const std::string& name, const std::string& what)
{
    if (name == "mm") return 0.001;
    if (name == "cm") return 0.01;
    if (name == "m") return 1.0;
    throw Error(what, "unknown unit '" + name + "' (mm, cm, m)");
}

RecordedLog readRecordedLog(const std::string& path, const ReadOptions& opt)
{
    return parseRecordedLog(readTextInput(path, "laser log"), path, opt);
}

RecordedLog parseRecordedLog(const std::string& text, const std::string& path, const ReadOptions& opt)
{
    std::istringstream in(text);
    RecordedLog log;
    log.path = path;
    log.unit_m = opt.unit_m;
    std::string line;
    for (int ln = 1; std::getline(in, line); ++ln) {
        if (blankOrComment(line)) continue;
        const std::string where = path + ":" + std::to_string(ln);
        auto bad = [&](const std::string& what) { problem(where, what, opt.lenient, log.skipped); };
        std::istringstream ss(line);
        std::vector<double> f;
        std::string tok, why;
        while (why.empty() && ss >> tok) {
            double v = 0;
            why = parseField(tok, f.size(), v);
            f.push_back(v);
        }
        if (!why.empty()) {
            bad(why);
            continue;
        }
        if (f.size() < 3 || (f.size() - 1) % 2 != 0) {
            bad("expected a time and (angle, range) pairs, got " + std::to_string(f.size()) + " fields");
            continue;
        }
        const size_t beams = (f.size() - 1) / 2;
        if (!log.scans.empty() && beams != log.scans.front().range.size()) {
            bad("has " + std::to_string(beams) + " beams where the first scan has " +
                std::to_string(log.scans.front().range.size()) + " (truncated line?)");
            continue;
        }
        if (!log.scans.empty() && f[0] <= log.scans.back().time_s) {
            bad(f[0] < log.scans.back().time_s ? "time goes backwards" : "time repeats the previous scan's");
            continue;
        }
        if (const std::string why = implausibleBeam(f, opt.unit_m); !why.empty()) {
            bad(why);
            continue;
        }
        LaserLogScan s;
        s.time_s = f[0];
        for (size_t i = 1; i < f.size(); i += 2) {
            s.angle_rad.push_back(f[i]);
            s.range.push_back(f[i + 1]);
        }
        log.scans.push_back(std::move(s));
    }
    if (log.scans.empty()) throw Error(path, "holds no scans");
    return log;
}

SaturationSeries readSaturationCsv(const std::string& path, const ReadOptions& opt)
{
    return parseSaturationCsv(readTextInput(path, "saturation CSV"), path, opt);
}

SaturationSeries parseSaturationCsv(const std::string& text, const std::string& path, const ReadOptions& opt)
{
    std::istringstream in(text);
    SaturationSeries s;
    s.path = path;
    int col_t = 0, col_s = 1;
    std::vector<int> patch_cols;
    bool first = true;
    std::string line;
    for (int ln = 1; std::getline(in, line); ++ln) {
        if (blankOrComment(line)) continue;
        const std::string where = path + ":" + std::to_string(ln);
        const auto f = splitCsv(line);
        if (first) {
            first = false;
            double v = 0;
            if (!f.empty() && !parseField(f[0], 0, v).empty()) {  // a header: columns by name
                col_t = col_s = -1;
                for (size_t i = 0; i < f.size(); ++i) {
                    if (f[i] == "time_s" || f[i] == "time")
                        col_t = int(i);
                    else if (f[i] == "saturation")
                        col_s = int(i);
                    else if (f[i] != "pixels" && !endsWith(f[i], "_median") && !endsWith(f[i], "_sd") &&
                             !f[i].empty()) {
                        patch_cols.push_back(int(i));
                        s.patch_names.push_back(f[i]);
                    }
                }
                if (col_t < 0 || col_s < 0) throw Error(where, "the header needs columns 'time_s' and 'saturation'");
                s.patch.resize(s.patch_names.size());
                continue;
            }
        }
        auto bad = [&](const std::string& what) { problem(where, what, opt.lenient, s.skipped); };
        const size_t need = size_t(std::max(col_t, col_s)) + 1;
        if (f.size() < need) {
            bad("expected at least " + std::to_string(need) + " fields, got " + std::to_string(f.size()));
            continue;
        }
        double t = 0, sat = 0;
        std::string why = parseField(f[size_t(col_t)], size_t(col_t), t);
        if (why.empty()) why = parseField(f[size_t(col_s)], size_t(col_s), sat);
        if (!why.empty()) {
            bad(why);
            continue;
        }
        if (sat < 0 || sat > 1) {
            bad("saturation " + f[size_t(col_s)] + " is outside [0, 1]");
            continue;
        }
        if (!s.time_s.empty() && t < s.time_s.back()) {
            bad("time goes backwards");
            continue;
        }
        std::vector<double> pv;
        for (size_t p = 0; why.empty() && p < patch_cols.size(); ++p) {
            const size_t c = size_t(patch_cols[p]);
            double v = NAN;
            if (c < f.size() && !f[c].empty()) {
                why = parseField(f[c], c, v);
                if (why.empty() && (v < 0 || v > 1))
                    why = "saturation " + f[c] + " of patch '" + s.patch_names[p] + "' is outside [0, 1]";
            }
            pv.push_back(v);
        }
        if (!why.empty()) {
            bad(why);
            continue;
        }
        s.time_s.push_back(t);
        s.saturation.push_back(sat);
        for (size_t p = 0; p < pv.size(); ++p) s.patch[p].push_back(pv[p]);
    }
    if (s.time_s.empty()) throw Error(path, "holds no saturation rows");
    return s;
}

void checkColumnName(const std::string& name, const std::string& where)
{
    bool ok = !name.empty() && name.size() <= 64;
    for (char c : name) ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.');
    if (!ok)
        throw Error(where, "name '" + name + "' must be 1-64 letters, digits, '_', '-' or '.' (it heads a CSV column)");
    if (name == "time_s" || name == "time" || name == "saturation" || name == "pixels" || endsWith(name, "_median") ||
        endsWith(name, "_sd"))
        throw Error(where, "name '" + name + "' is one of the CSV's own columns");
}

void writeSaturationCsv(const std::string& path, const SaturationSeries& s, const std::vector<std::string>& header)
{
    for (const auto& n : s.patch_names) checkColumnName(n, path);
    AtomicFile f(path);
    std::ostream& o = f.stream();
    for (const auto& h : header) o << "# " << h << '\n';
    const bool spread = !s.median.empty();
    o << "time_s,saturation";
    if (spread) o << ",saturation_median,saturation_sd,pixels";
    for (const auto& n : s.patch_names) {
        o << ',' << n;
        if (spread) o << ',' << n << "_median," << n << "_sd";
    }
    o << '\n' << std::setprecision(9);
    auto value = [&](double v) {
        o << ',';
        if (std::isfinite(v)) o << v;
    };
    for (size_t k = 0; k < s.time_s.size(); ++k) {
        o << shortest(s.time_s[k]) << ',' << s.saturation[k];
        if (spread) {
            value(s.median[k]);
            value(s.sd[k]);
            value(s.pixels[k]);
        }
        for (size_t p = 0; p < s.patch.size(); ++p) {
            value(s.patch[p][k]);
            if (spread) {
                value(s.patch_median[p][k]);
                value(s.patch_sd[p][k]);
            }
        }
        o << '\n';
    }
    f.commit();
}

}  // namespace smokescan
