#include "smokescan/camera/frame_saturation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <regex>
#include <sstream>

#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/io/recorded.hpp"
#include "smokescan/io/text_input.hpp"
#include "smokescan/render/renderer.hpp"

namespace smokescan {
namespace {

namespace fs = std::filesystem;

}  // namespace

double frameTimeFromName(const std::string& path, double fps)
{
    const std::string stem = fs::path(path).stem().string();
    static const std::regex num(R"(\d+(\.\d+)?)");
    std::string last;
    for (auto it = std::sregex_iterator(stem.begin(), stem.end(), num); it != std::sregex_iterator(); ++it)
        last = it->str();
    if (last.empty()) throw Error(path, "has no number in its name to take the time from (use --timestamps)");
    const double v = std::stod(last);
    return fps > 0 ? v / fps : v;
}

std::vector<double> readFrameTimestamps(const std::string& path, const std::vector<std::string>& frames)
{
    std::istringstream in(readTextInput(path, "timestamps file"));
    std::map<std::string, double> by_name;
    std::vector<double> in_order;
    std::string line;
    for (int ln = 1; std::getline(in, line); ++ln) {
        if (line.empty() || line[0] == '#') continue;
        const auto comma = line.find(',');
        const std::string t = comma == std::string::npos ? line : line.substr(comma + 1);
        char* end = nullptr;
        const double v = std::strtod(t.c_str(), &end);
        while (end && (*end == ' ' || *end == '\t' || *end == '\r')) ++end;  // trailing blanks only
        if (end == t.c_str() || *end || !std::isfinite(v)) {
            if (ln == 1) continue;  // a header
            throw Error(path + ":" + std::to_string(ln), "time is not a finite number: '" + t + "'");
        }
        if (comma == std::string::npos)
            in_order.push_back(v);
        else
            by_name[fs::path(line.substr(0, comma)).filename().string()] = v;
    }
    std::vector<double> out;
    for (size_t i = 0; i < frames.size(); ++i) {
        const auto it = by_name.find(fs::path(frames[i]).filename().string());
        if (it != by_name.end())
            out.push_back(it->second);
        else if (i < in_order.size())
            out.push_back(in_order[i]);
        else
            throw Error(path, "has no time for " + frames[i]);
    }
    return out;
}

namespace {

/// Each pixel's patch (index into names, −1: none): polygons first, then the object id.
std::vector<int> labelPixels(const Image& img, const Image* ids, const FrameRegions& regions,
                             const std::vector<std::string>& names)
{
    const int object_ch = ids ? ids->channel("object", 0) : 0;
    std::vector<int> label(size_t(img.width) * img.height, -1);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const std::string* n = nullptr;
            for (const auto& p : regions.patches)
                if (insidePolygon(p.polygon_px, x + 0.5, y + 0.5)) {
                    n = &p.name;
                    break;
                }
            if (!n && ids) {
                const int p = regions.target.of(int(ids->at(x, y, object_ch)));
                if (p >= 0) n = &regions.target.names[size_t(p)];
            }
            if (n) label[size_t(y) * img.width + x] = int(std::find(names.begin(), names.end(), *n) - names.begin());
        }
    return label;
}

}  // namespace

bool insidePolygon(const std::vector<std::pair<double, double>>& p, double x, double y)
{
    bool in = false;
    for (size_t i = 0, j = p.size() - 1; i < p.size(); j = i++)
        if ((p[i].second > y) != (p[j].second > y) &&
            x < (p[j].first - p[i].first) * (y - p[i].second) / (p[j].second - p[i].second) + p[i].first)
            in = !in;
    return in;
}

FramePatch parseFramePatch(const std::string& spec, bool rect, const std::string& option)
{
    const auto eq = spec.find('=');
    if (eq == std::string::npos || eq == 0) throw Error(option, "expects NAME=numbers, got '" + spec + "'");
    FramePatch p;
    p.name = spec.substr(0, eq);
    checkColumnName(p.name, option);
    const auto v = parseNumberList(spec.substr(eq + 1), option);
    if (rect) {
        if (v.size() != 4 || v[2] <= 0 || v[3] <= 0)
            throw Error(option, "expects NAME=x,y,width,height with a positive size");
        p.polygon_px = {{v[0], v[1]}, {v[0] + v[2], v[1]}, {v[0] + v[2], v[1] + v[3]}, {v[0], v[1] + v[3]}};
    } else {
        if (v.size() < 6 || v.size() % 2) throw Error(option, "expects NAME=x1,y1,x2,y2,x3,y3,... (at least 3 points)");
        for (size_t i = 0; i < v.size(); i += 2) p.polygon_px.emplace_back(v[i], v[i + 1]);
    }
    return p;
}

std::vector<std::string> listFrames(const std::vector<std::string>& inputs)
{
    std::vector<std::string> out;
    for (const auto& in : inputs) {
        if (fs::is_directory(in)) {
            std::vector<std::string> v;
            for (const auto& e : fs::directory_iterator(in))
                if (e.is_regular_file() && isImageExtension(e.path().string())) v.push_back(e.path().string());
            std::sort(v.begin(), v.end());
            if (v.empty()) throw Error(in, "holds no images");
            out.insert(out.end(), v.begin(), v.end());
        } else {
            if (!fs::exists(in)) throw Error(in, "no such file");
            if (!fs::is_regular_file(in)) throw Error(in, "is not a regular file (a frame is an image file)");
            out.push_back(in);
        }
    }
    return out;
}

std::vector<std::string> FrameRegions::names() const
{
    std::vector<std::string> n;
    for (const auto& p : patches) n.push_back(p.name);
    for (const auto& t : target.names)
        if (std::find(n.begin(), n.end(), t) == n.end()) n.push_back(t);
    return n;
}

FrameSaturation measureFrame(const Image& img, bool linear, const Image* ids, const FrameRegions& regions,
                             const std::vector<std::string>& names)
{
    // Linear frames are encoded as the camera delivers them before measuring.
    Image disp = img;
    if (linear)
        for (float& v : disp.data) v = float(srgbEncode(std::clamp(double(v), 0.0, 1.0)));
    const std::vector<int> label = labelPixels(img, regions.by_id ? ids : nullptr, regions, names);
    auto labelAt = [&](int x, int y) { return label[size_t(y) * img.width + x]; };
    FrameSaturation out;
    out.all = maskedSaturation(disp, [&](int x, int y) { return labelAt(x, y) >= 0; });
    for (size_t i = 0; i < names.size(); ++i)
        out.patch.push_back(maskedSaturation(disp, [&](int x, int y) { return labelAt(x, y) == int(i); }));
    return out;
}

FrameRegions frameRegions(const std::vector<std::string>& rects, const std::vector<std::string>& polygons)
{
    FrameRegions regions;
    for (const auto& r : rects) regions.patches.push_back(parseFramePatch(r, true, "--rect"));
    for (const auto& p : polygons) regions.patches.push_back(parseFramePatch(p, false, "--polygon"));
    const auto& patches = regions.patches;
    for (size_t i = 0; i < patches.size(); ++i)
        for (size_t j = 0; j < i; ++j)
            if (patches[i].name == patches[j].name)
                throw Error("--rect/--polygon", "patch '" + patches[i].name + "' is named twice");
    return regions;
}

FrameSeries::FrameSeries(const FrameRegions& regions) : regions_(regions)
{
    s_.patch_names = regions.names();
    const size_t P = s_.patch_names.size();
    s_.patch.resize(P);
    s_.patch_median.resize(P);
    s_.patch_sd.resize(P);
}

void FrameSeries::add(const Image& frame, bool linear, const Image* ids, double time_s, const std::string& name)
{
    if (s_.time_s.empty()) {
        width_ = frame.width, height_ = frame.height;
        // A patch reaching past the frame would be measured on the part inside, silently.
        for (const FramePatch& p : regions_.patches)
            for (const auto& [x, y] : p.polygon_px)
                if (!(x >= 0 && x <= width_ && y >= 0 && y <= height_))
                    throw Error(name,
                                fmt("patch '%s' reaches (%g, %g), outside the %d×%d frame", p.name.c_str(), x, y,
                                    width_, height_));
    } else if (frame.width != width_ || frame.height != height_) {
        throw Error(name,
                    fmt("is %d×%d pixels, the first frame %d×%d (the patches are in its pixels)", frame.width,
                        frame.height, width_, height_));
    }
    const FrameSaturation m = measureFrame(frame, linear, ids, regions_, s_.patch_names);
    if (m.all.pixels == 0) throw Error(name, "the target region holds no pixels");
    if (!s_.time_s.empty() && !(time_s > s_.time_s.back()))
        throw Error(name,
                    fmt("its time %.6g s does not follow the previous frame's (%.6g s): frames are measured in "
                        "time order, each once",
                        time_s, s_.time_s.back()));
    s_.time_s.push_back(time_s);
    s_.saturation.push_back(m.all.mean);
    s_.median.push_back(m.all.median);
    s_.sd.push_back(m.all.stddev);
    s_.pixels.push_back(double(m.all.pixels));
    for (size_t p = 0; p < s_.patch_names.size(); ++p) {
        const bool any = m.patch[p].pixels > 0;
        s_.patch[p].push_back(any ? m.patch[p].mean : NAN);
        s_.patch_median[p].push_back(any ? m.patch[p].median : NAN);
        s_.patch_sd[p].push_back(any ? m.patch[p].stddev : NAN);
    }
}

SaturationSeries measureFrames(const std::vector<std::string>& frames, const std::vector<std::string>& id_frames,
                               const std::function<double(size_t)>& time_of, const FrameRegions& regions)
{
    FrameSeries series(regions);
    for (size_t k = 0; k < frames.size(); ++k) {
        const Image img = readImage(frames[k]);
        if (img.channels < 3 || (!img.channel_names.empty() && img.channel("R", -1) < 0))
            throw Error(frames[k], "is not an RGB image (an id image among the frames?)");
        Image ids;
        if (regions.by_id) {
            ids = readImage(id_frames[k]);
            if (ids.width != img.width || ids.height != img.height)
                throw Error(id_frames[k], "size differs from " + frames[k]);
            if (ids.channel("object", -1) < 0) throw Error(id_frames[k], "has no 'object' channel (not an id image)");
        }
        const bool linear = fs::path(frames[k]).extension() == ".exr";
        series.add(img, linear, regions.by_id ? &ids : nullptr, time_of(k), frames[k]);
    }
    return series.take();
}

}  // namespace smokescan
