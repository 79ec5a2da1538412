#include "smokescan/lidar/frame_index.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/io/text_input.hpp"
#include "smokescan/lidar/point_cloud_io.hpp"

namespace smokescan {
namespace {

constexpr size_t kFields = 18;  ///< frame, file, start_s, end_s, two poses of seven numbers

std::vector<std::string> splitFields(const std::string& line)
{
    std::vector<std::string> out;
    std::stringstream ss(line);
    std::string f;
    while (std::getline(ss, f, ',')) out.push_back(f);
    if (!line.empty() && line.back() == ',') out.emplace_back();
    return out;
}

/// Seven numbers from fields[k..k+7): x y z qw qx qy qz.
Pose poseOf(const std::vector<std::string>& fields, size_t k, const std::string& where)
{
    double v[7];
    for (size_t j = 0; j < 7; ++j) v[j] = parseFiniteNumber(fields[k + j], where);
    const Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1) > 1e-3)
        throw Error(where,
                    "the quaternion (" + fields[k + 3] + ", " + fields[k + 4] + ", " + fields[k + 5] + ", " +
                        fields[k + 6] + ") is not of norm 1");
    Pose p;
    p.t = Vec3(v[0], v[1], v[2]);
    p.R = q.normalized().toRotationMatrix();
    return p;
}

uint64_t frameNumber(const std::string& text, const std::string& where)
{
    if (text.empty() || text.size() > 19 || text.find_first_not_of("0123456789") != std::string::npos)
        throw Error(where, "frame '" + text + "' is not a frame index (a whole number)");
    return std::stoull(text);
}

}  // namespace

std::vector<FrameIndexEntry> parseFrameIndex(const std::string& text, const std::string& name)
{
    std::stringstream in(text);
    std::string line, header = frameIndexHeader();
    header.pop_back();
    size_t number = 0;
    std::vector<FrameIndexEntry> out;
    std::set<std::string> files;
    while (std::getline(in, line)) {
        ++number;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        const std::string where = name + ":" + std::to_string(number);
        if (number == 1) {
            if (line != header) throw Error(where, "the header is not frames.csv's (" + header.substr(0, 30) + "...)");
            continue;
        }
        if (line.empty()) continue;
        // Counted before splitting: a line of millions of commas is refused, not split.
        const size_t fields = size_t(std::count(line.begin(), line.end(), ',')) + 1;
        if (fields != kFields)
            throw Error(where, std::to_string(fields) + " fields (frames.csv has " + std::to_string(kFields) + ")");
        const std::vector<std::string> f = splitFields(line);
        if (out.size() >= size_t(limits::kFrames))
            throw Error(where, "more than " + std::to_string(limits::kFrames) + " frames");
        FrameIndexEntry e;
        e.frame = frameNumber(f[0], where);
        e.file = f[1];
        if (e.file.empty() || e.file == "." || e.file == ".." || e.file.find('/') != std::string::npos)
            throw Error(where, "file '" + e.file + "' is not a file name inside the folder");
        if (!files.insert(e.file).second) throw Error(where, "file '" + e.file + "' is listed twice");
        e.start_s = parseFiniteNumber(f[2], where);
        e.end_s = parseFiniteNumber(f[3], where);
        if (!(e.end_s >= e.start_s)) throw Error(where, "end_s " + f[3] + " precedes start_s " + f[2]);
        if (!out.empty() && !(e.start_s > out.back().start_s))
            throw Error(where, "start_s " + f[2] + " does not follow the previous frame's (frames in time order)");
        e.start_pose = poseOf(f, 4, where);
        e.end_pose = poseOf(f, 11, where);
        out.push_back(std::move(e));
    }
    if (number == 0) throw Error(name, "is empty (frames.csv starts with its header)");
    return out;
}

std::vector<FrameIndexEntry> readFrameIndex(const std::string& dir)
{
    const std::string path = dir + "/frames.csv";
    return parseFrameIndex(readTextInput(path, "frame index"), path);
}

}  // namespace smokescan
