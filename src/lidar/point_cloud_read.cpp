// Point-cloud frames read back (point_cloud_io.hpp: readPointCloud): PCD v0.7 (ascii or binary)
// and PLY 1.0 (ascii or binary little endian), smokescan's own and lidar drivers' fields.
#include <Eigen/Geometry>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <sstream>

#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/io/text_input.hpp"
#include "smokescan/lidar/lidar_spec.hpp"
#include "smokescan/lidar/point_cloud_io.hpp"

namespace smokescan {
namespace {

/// One field of a record: where it lies and how it is stored.
struct Field {
    std::string name;
    char type = 'F';  ///< F float, U unsigned, I signed
    int size = 4;  ///< bytes of one value
    int count = 1;
    size_t offset = 0;  ///< bytes from the record's start (binary); first token (ascii)
};

/// The fields smokescan takes, by the names drivers give them.
enum class Slot { X, Y, Z, Intensity, Ring, Return, Time, TimeNs, Source, None };

Slot slotOf(const std::string& name)
{
    static const std::pair<const char*, Slot> kNames[] = {{"x", Slot::X},           {"y", Slot::Y},
                                                          {"z", Slot::Z},           {"intensity", Slot::Intensity},
                                                          {"ring", Slot::Ring},     {"return_index", Slot::Return},
                                                          {"return", Slot::Return}, {"time", Slot::Time},
                                                          {"t", Slot::TimeNs},      {"source", Slot::Source}};
    for (const auto& [n, s] : kNames)
        if (name == n) return s;
    return Slot::None;
}

/// A header line at `at` (without its newline), `at` moved past it; throws past `end_of_header`.
std::string headerLine(const std::string& bytes, size_t& at, const std::string& where)
{
    const size_t nl = bytes.find('\n', at);
    if (nl == std::string::npos || nl - at > 65536) throw Error(where, "the header ends without its data");
    std::string line = bytes.substr(at, nl - at);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    at = nl + 1;
    return line;
}

std::vector<std::string> words(const std::string& line)
{
    std::istringstream in(line);
    std::vector<std::string> w;
    for (std::string s; in >> s;) w.push_back(s);
    return w;
}

long long wholeNumber(const std::string& text, const std::string& where, const std::string& what, long long max)
{
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || *end || errno == ERANGE || v < 0 || v > max)
        throw Error(where, what + " '" + text + "' is not a whole number from 0 to " + std::to_string(max));
    return v;
}

/// The pose "tx ty tz qw qx qy qz" from seven words into out.viewpoint; false (out unchanged) for a
/// zero quaternion. @throw Error(where) for a word that is not a finite number.
bool readViewpoint(const std::string* seven, const std::string& where, PointCloudFile& out)
{
    double q[7];
    for (size_t i = 0; i < 7; ++i) q[i] = parseFiniteNumber(seven[i], where);
    const Eigen::Quaterniond rot(q[3], q[4], q[5], q[6]);
    if (!(rot.norm() > 1e-9)) return false;
    out.viewpoint.t = Vec3(q[0], q[1], q[2]);
    out.viewpoint.R = rot.normalized().toRotationMatrix();
    out.has_viewpoint = true;
    return true;
}

/// A value of `f` stored little endian at p.
double binaryValue(const char* p, const Field& f)
{
    auto get = [p](auto v) {
        std::memcpy(&v, p, sizeof v);
        return double(v);
    };
    if (f.type == 'F') return f.size == 4 ? get(float()) : get(double());
    if (f.type == 'U')
        return f.size == 1 ? get(uint8_t())
            : f.size == 2  ? get(uint16_t())
            : f.size == 4  ? get(uint32_t())
                           : get(uint64_t());
    return f.size == 1 ? get(int8_t()) : f.size == 2 ? get(int16_t()) : f.size == 4 ? get(int32_t()) : get(int64_t());
}

void checkType(const Field& f, const std::string& where)
{
    const bool ok = f.type == 'F'
        ? (f.size == 4 || f.size == 8)
        : (f.type == 'U' || f.type == 'I') && (f.size == 1 || f.size == 2 || f.size == 4 || f.size == 8);
    if (!ok)
        throw Error(where, "field '" + f.name + "' has type " + f.type + " of " + std::to_string(f.size) + " bytes");
    if (slotOf(f.name) != Slot::None && f.count != 1)
        throw Error(where, "field '" + f.name + "' has " + std::to_string(f.count) + " values a point, not 1");
}

/// v as a float, ±inf beyond its range (a double's 1e300), NaN kept.
float toFloat(double v)
{
    if (std::abs(v) <= double(std::numeric_limits<float>::max())) return float(v);
    return v > 0 ? std::numeric_limits<float>::infinity() : v < 0 ? -std::numeric_limits<float>::infinity() : float(v);
}

/// v within [0, max] (NaN as 0): for the integer fields.
double bounded(double v, double max) { return v >= 0 ? (v <= max ? v : max) : 0.0; }

/// Sets one slot of the point from a field's value.
void put(LidarPoint& p, Slot s, double v)
{
    switch (s) {
    case Slot::X:
        p.x = toFloat(v);
        break;
    case Slot::Y:
        p.y = toFloat(v);
        break;
    case Slot::Z:
        p.z = toFloat(v);
        break;
    case Slot::Intensity:
        p.intensity = toFloat(v);
        break;
    case Slot::Ring:
        p.ring = uint16_t(bounded(v, 65535));
        break;
    case Slot::Return:
        p.return_index = uint8_t(bounded(v, 255));
        break;
    case Slot::Time:
        p.time_s = toFloat(v);
        break;
    case Slot::TimeNs:
        p.time_s = toFloat(v * 1e-9);
        break;
    case Slot::Source:
        p.source = uint8_t(bounded(v, 255));
        break;
    case Slot::None:
        break;
    }
}

/// The points of a body, binary or ascii, `n` records of `fields`.
/// `stride`: bytes from one binary record to the next (0: the fields' sizes, packed).
void readBody(const std::string& bytes, size_t at, bool binary, long long n, const std::vector<Field>& fields,
              const std::string& path, PointCloudFile& out, size_t stride = 0)
{
    size_t record = 0, tokens = 0;
    for (const Field& f : fields) {
        record += size_t(f.size) * size_t(f.count);
        tokens += size_t(f.count);
    }
    if (stride > 0) record = stride;
    std::vector<Slot> slots;
    for (const Field& f : fields) slots.push_back(slotOf(f.name));
    auto finish = [&](LidarPoint& p) {
        if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) {
            ++out.skipped;  // a driver's "no return" in an organised cloud
            out.skipped_first += p.return_index == 0;
            return;
        }
        p.range_m = std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
        p.beam = uint32_t(out.points.size() + out.skipped);
        out.points.push_back(p);
    };
    // Room for the points the bytes can hold, not for what a header claims.
    const size_t room = (bytes.size() - std::min(at, bytes.size())) / (binary ? record : 2 * tokens);
    out.points.reserve(std::min(size_t(n), room));
    if (binary) {
        if (room < size_t(n))
            throw Error(path,
                        "holds " + std::to_string(room) + " whole points of the " + std::to_string(n) +
                            " its header gives (truncated)");
        for (long long i = 0; i < n; ++i) {
            LidarPoint p;
            const char* r = bytes.data() + at + size_t(i) * record;
            for (size_t k = 0; k < fields.size(); ++k) put(p, slots[k], binaryValue(r + fields[k].offset, fields[k]));
            finish(p);
        }
        return;
    }
    const long long header_lines = std::count(bytes.begin(), bytes.begin() + long(at), '\n');
    for (long long i = 0; i < n; ++i) {
        const std::string where = path + ":" + std::to_string(header_lines + 1 + i);
        if (at >= bytes.size())
            throw Error(where, "the file ends after " + std::to_string(i) + " of " + std::to_string(n) + " points");
        size_t nl = bytes.find('\n', at);
        if (nl == std::string::npos) nl = bytes.size();
        if (nl - at > 65536) throw Error(where, "a line of more than 64 KiB");
        const std::vector<std::string> w = words(bytes.substr(at, nl - at));
        at = nl + 1;
        if (w.size() != tokens)
            throw Error(where,
                        std::to_string(w.size()) + " values, not the " + std::to_string(tokens) + " the header gives");
        LidarPoint p;
        size_t t = 0;
        for (size_t k = 0; k < fields.size(); t += size_t(fields[k].count), ++k) {
            if (slots[k] == Slot::None) continue;
            const std::string& s = w[t];
            const bool nan = s == "nan" || s == "NaN" || s == "-nan";
            put(p, slots[k], nan ? NAN : parseFiniteNumber(s, where));
        }
        finish(p);
    }
}

/// Each field once (a second 'x' would be read in place of the first), and x, y and z among them.
void requireXyz(const std::vector<Field>& fields, const std::string& path)
{
    // The value a field holds: two names drivers give one (time and Ouster's t, return and return_index).
    auto value = [](const std::string& n) { return slotOf(n) == Slot::TimeNs ? Slot::Time : slotOf(n); };
    for (size_t i = 0; i < fields.size(); ++i)
        for (size_t j = 0; j < i; ++j) {
            if (fields[i].name == fields[j].name) throw Error(path, "has the field '" + fields[i].name + "' twice");
            if (value(fields[i].name) != Slot::None && value(fields[i].name) == value(fields[j].name))
                throw Error(path,
                            "has the fields '" + fields[j].name + "' and '" + fields[i].name +
                                "', which both name one value of a point: which holds it?");
        }
    for (const char* axis : {"x", "y", "z"}) {
        bool found = false;
        for (const Field& f : fields) found = found || f.name == axis;
        if (!found) throw Error(path, std::string("has no field '") + axis + "'");
    }
}

PointCloudFile readPcd(const std::string& path, const std::string& bytes)
{
    PointCloudFile out;
    std::vector<Field> fields;
    std::vector<std::string> sizes, types, counts;
    long long width = -1, height = 1, points = -1;
    size_t at = 0;
    const long long max_points = 2 * lidar_limits::kBeamsPerFrame;
    for (int line_no = 1;; ++line_no) {
        const std::string where = path + ":" + std::to_string(line_no);
        if (line_no > 1000) throw Error(where, "a PCD header of more than 1000 lines");
        const std::string line = headerLine(bytes, at, where);
        if (line.empty()) continue;
        if (line[0] == '#') {
            // smokescan's own: "(smokescan lidar frame N, start_s T)"; other comments are comments.
            const size_t s = line.find("start_s ");
            if (s != std::string::npos) {
                char* end = nullptr;
                const double t = std::strtod(line.c_str() + s + 8, &end);
                if (end != line.c_str() + s + 8 && std::isfinite(t)) out.start_s = t;
            }
            continue;
        }
        const std::vector<std::string> w = words(line);
        if (w.empty()) continue;  // a line of blanks
        const std::string& key = w[0];
        const std::vector<std::string> v(w.begin() + 1, w.end());
        if (key == "VERSION") continue;
        if (key == "FIELDS") {
            if (v.empty() || v.size() > 256) throw Error(where, "FIELDS must name 1 to 256 fields");
            for (const std::string& n : v) fields.push_back({n});
        } else if (key == "SIZE")
            sizes = v;
        else if (key == "TYPE")
            types = v;
        else if (key == "COUNT")
            counts = v;
        else if (key == "WIDTH")
            width = wholeNumber(v.empty() ? "" : v[0], where, "WIDTH", max_points);
        else if (key == "HEIGHT")
            height = wholeNumber(v.empty() ? "" : v[0], where, "HEIGHT", max_points);
        else if (key == "POINTS")
            points = wholeNumber(v.empty() ? "" : v[0], where, "POINTS", max_points);
        else if (key == "VIEWPOINT") {
            if (v.size() != 7) throw Error(where, "VIEWPOINT needs tx ty tz qw qx qy qz");
            if (!readViewpoint(v.data(), where, out)) throw Error(where, "VIEWPOINT's quaternion is zero");
        } else if (key == "DATA") {
            const std::string mode = v.empty() ? "" : v[0];
            if (mode != "ascii" && mode != "binary")
                throw Error(where, "DATA " + mode + " is not read (ascii or binary; binary_compressed is not)");
            if (fields.empty()) throw Error(where, "DATA before FIELDS");
            if (sizes.size() != fields.size() || types.size() != fields.size() ||
                (!counts.empty() && counts.size() != fields.size()))
                throw Error(where,
                            "SIZE, TYPE and COUNT must give one value for each of the " +
                                std::to_string(fields.size()) + " fields");
            size_t offset = 0;
            for (size_t i = 0; i < fields.size(); ++i) {
                Field& f = fields[i];
                f.size = int(wholeNumber(sizes[i], where, "SIZE", 8));
                if (types[i].size() != 1) throw Error(where, "TYPE '" + types[i] + "' is not F, U or I");
                f.type = types[i][0];
                f.count = counts.empty() ? 1 : int(wholeNumber(counts[i], where, "COUNT", 1024));
                if (f.count < 1) throw Error(where, "field '" + f.name + "' has COUNT 0");
                checkType(f, where);
                f.offset = offset;
                offset += size_t(f.size) * size_t(f.count);
            }
            requireXyz(fields, path);
            if (points < 0) points = width < 0 ? -1 : width * height;
            if (points < 0) throw Error(where, "the header gives neither POINTS nor WIDTH");
            if (width >= 0 && width * height != points)
                throw Error(where, "POINTS " + std::to_string(points) + " is not WIDTH × HEIGHT");
            readBody(bytes, at, mode == "binary", points, fields, path, out);
            for (const Field& f : fields) out.fields.push_back(f.name);
            return out;
        } else
            throw Error(where, "'" + key + "' is not a PCD header line");
    }
}

PointCloudFile readPly(const std::string& path, const std::string& bytes)
{
    PointCloudFile out;
    size_t at = 0;
    std::vector<Field> fields;
    long long points = -1;
    bool binary = false, in_vertex = false, format = false;
    const long long max_points = 2 * lidar_limits::kBeamsPerFrame;
    static const std::pair<const char*, std::pair<char, int>> kTypes[] = {
        {"char", {'I', 1}},  {"uchar", {'U', 1}},  {"short", {'I', 2}},   {"ushort", {'U', 2}},
        {"int", {'I', 4}},   {"uint", {'U', 4}},   {"float", {'F', 4}},   {"double", {'F', 8}},
        {"int8", {'I', 1}},  {"uint8", {'U', 1}},  {"int16", {'I', 2}},   {"uint16", {'U', 2}},
        {"int32", {'I', 4}}, {"uint32", {'U', 4}}, {"float32", {'F', 4}}, {"float64", {'F', 8}}};
    for (int line_no = 1;; ++line_no) {
        const std::string where = path + ":" + std::to_string(line_no);
        if (line_no > 1000) throw Error(where, "a PLY header of more than 1000 lines");
        const std::string line = headerLine(bytes, at, where);
        const std::vector<std::string> w = words(line);
        if (line_no == 1) {
            if (line != "ply") throw Error(where, "is not a PLY file (its first line is not 'ply')");
            continue;
        }
        if (w.empty()) continue;
        if (w[0] == "comment") {
            if (w.size() >= 3 && w[1] == "start_s") out.start_s = parseFiniteNumber(w[2], where);
            if (w.size() == 9 && w[1] == "viewpoint") readViewpoint(&w[2], where, out);  // a zero one: none
        } else if (w[0] == "format") {
            if (w.size() != 3 || (w[1] != "ascii" && w[1] != "binary_little_endian"))
                throw Error(where, "'" + line + "': ascii or binary_little_endian 1.0 are read");
            binary = w[1] == "binary_little_endian";
            format = true;
        } else if (w[0] == "element") {
            if (w.size() != 3) throw Error(where, "'" + line + "' is not 'element NAME COUNT'");
            if (points >= 0 && in_vertex) in_vertex = false;  // later elements follow the vertices: ignored
            if (w[1] == "vertex") {
                if (points >= 0) throw Error(where, "a second vertex element");
                points = wholeNumber(w[2], where, "the vertex count", max_points);
                in_vertex = true;
            } else if (points < 0)
                throw Error(where, "element '" + w[1] + "' before the vertices is not read");
        } else if (w[0] == "property") {
            if (!in_vertex) continue;
            if (w.size() != 3) throw Error(where, "'" + line + "': the vertices' properties must be scalars");
            Field f{w[2]};
            bool known = false;
            for (const auto& [n, t] : kTypes)
                if (w[1] == n) f.type = t.first, f.size = t.second, known = true;
            if (!known) throw Error(where, "property type '" + w[1] + "' is not a PLY scalar type");
            f.offset = fields.empty() ? 0 : fields.back().offset + size_t(fields.back().size);
            fields.push_back(f);
        } else if (w[0] == "end_header") {
            if (!format) throw Error(where, "the header has no format line");
            if (points < 0) throw Error(where, "the header has no vertex element");
            requireXyz(fields, path);
            for (const Field& f : fields) checkType(f, where);
            readBody(bytes, at, binary, points, fields, path, out);
            for (const Field& f : fields) out.fields.push_back(f.name);
            return out;
        } else if (w[0] != "obj_info")
            throw Error(where, "'" + w[0] + "' is not a PLY header line");
    }
}

}  // namespace

PointCloudFile readPointRecords(const std::string& bytes, long long n, size_t stride,
                                const std::vector<PointRecordField>& given, const std::string& name)
{
    if (n < 0 || n > 2 * lidar_limits::kBeamsPerFrame)
        throw Error(
            name,
            std::to_string(n) + " points (at most " + std::to_string(2 * lidar_limits::kBeamsPerFrame) + " a frame)");
    if (given.empty() || given.size() > 256)
        throw Error(name, "1 to 256 fields a point, not " + std::to_string(given.size()));
    if (stride == 0) throw Error(name, "points of 0 bytes");
    std::vector<Field> fields;
    for (const PointRecordField& g : given) {
        Field f{g.name, g.type, g.size, g.count, g.offset};
        if (f.count < 1 || f.count > 1024)
            throw Error(name, "field '" + f.name + "' has a count of " + std::to_string(f.count));
        checkType(f, name);
        if (f.offset > stride || size_t(f.size) * size_t(f.count) > stride - f.offset)
            throw Error(name,
                        "field '" + f.name + "' (at byte " + std::to_string(f.offset) +
                            ") does not fit in a point of " + std::to_string(stride) + " bytes");
        fields.push_back(f);
    }
    requireXyz(fields, name);
    PointCloudFile out;
    readBody(bytes, 0, true, n, fields, name, out, stride);
    for (const Field& f : fields) out.fields.push_back(f.name);
    return out;
}

PointCloudFile parsePointCloud(const std::string& bytes, const std::string& name)
{
    // By the content, or by the name's suffix (a .ply that does not open with 'ply' is named a bad PLY).
    const bool ply_name = name.size() >= 4 &&
        (name.compare(name.size() - 4, 4, ".ply") == 0 || name.compare(name.size() - 4, 4, ".PLY") == 0);
    if (bytes.rfind("ply", 0) == 0 || ply_name) return readPly(name, bytes);
    return readPcd(name, bytes);
}

PointCloudFile readPointCloud(const std::string& path)
{
    return parsePointCloud(readInputBytes(path, "point-cloud file", limits::kPointCloudBytes), path);
}

}  // namespace smokescan
