// `smokescan calibrate` (the paper's Fig. 7) and `smokescan saturation` (target saturation of frames).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <regex>
#include <sstream>

#include "commands.hpp"
#include "smokescan/calib/calibration.hpp"
#include "smokescan/camera/saturation_render.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/io/run_files.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/io/text_input.hpp"

namespace smokescan::cli {
namespace {
namespace fs = std::filesystem;

std::vector<double> parseList(const std::string& s, const std::string& what)
{
    std::vector<double> v;
    std::stringstream ss(s);
    std::string tok;
    while (std::getline(ss, tok, ',')) {
        char* end = nullptr;
        const double x = std::strtod(tok.c_str(), &end);
        if (tok.empty() || *end || !std::isfinite(x)) throw Error(what, "'" + tok + "' is not a finite number");
        v.push_back(x);
    }
    return v;
}

struct CalibArgs {
    std::string scene = "bocas", out, plot, densities;
    CalibrateConfig cfg;
};

int runCalibrate(const CalibArgs& a)
{
    CalibrateConfig cfg = a.cfg;
    if (!a.densities.empty()) cfg.densities = parseList(a.densities, "--densities");
    if (cfg.densities.size() > size_t(limits::kCalibrationDensities))
        throw Error("--densities", "at most " + std::to_string(limits::kCalibrationDensities) + " densities");
    for (double d : cfg.densities)
        if (d < 0 || d > limits::kCalibrationDensityMax)
            throw Error("--densities", "density " + std::to_string(d) + " is outside [0, " + std::to_string(limits::kCalibrationDensityMax) +
                                           "] (the calibration's range; 0.0028 is the paper's threshold)");
    if (double(cfg.width) * cfg.height * cfg.spp > double(limits::kFrameSamples))
        throw Error("--spp", "width × height × spp is over " + std::to_string(limits::kFrameSamples) + " samples a frame");
    RunFiles files;
    files.input(a.scene, "the scene");
    files.output(a.out, "--out");
    files.output(a.plot, "--plot");
    if (!a.plot.empty() && !isImageExtension(a.plot)) throw Error(a.plot, "unknown image format (png, exr, jpg, tif)");
    const Scene scene = loadScene(a.scene);
    const bool tty = ::isatty(2);
    const auto t0 = std::chrono::steady_clock::now();
    const CalibrationResult r = calibrate(scene, cfg, [&](int done, int total) {
        if (!tty) return;
        const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const int w = 30, k = w * done / total;
        std::fprintf(stderr, "\rcalibrate [%.*s%*s] %d/%d frames  %.0f s, ETA %.0f s ", k,
                     "==============================", w - k, "", done, total, el, el * (total - done) / done);
        if (done == total) std::fprintf(stderr, "\n");
    });
    if (!r.fit.converged)
        throw Error("calibrate", "the curve could not be fitted to these " + std::to_string(cfg.densities.size()) +
                                     " points: " + r.fit.message + " (the default sweep: 14 densities from 0 to 0.012)");
    writeCalibrationJson(files.stage(a.out), r, cfg, scene.source);
    if (!a.plot.empty()) writeCalibrationPlot(files.stage(a.plot), r, cfg);
    files.commit();
    const auto& f = r.fit;
    std::printf("fit: S0 = %.4f ± %.4f, a = %.4f ± %.4f, b = %.1f ± %.1f /density; chi2/dof = %.2f, R² = %.5f%s\n",
                f.curve.S0, f.std_error[0], f.curve.a, f.std_error[1], f.curve.b, f.std_error[2],
                f.dof > 0 ? f.chi2 / f.dof : 0.0, f.r2, f.converged ? "" : " (NOT CONVERGED)");
    std::printf("saturation %.2f at density %.5f ± %.5f; penetration power over %.2f m = %.5f ± %.5f density·m "
                "(paper: 0.0028, 0.007); engine unit factor %.3f\n",
                cfg.threshold_saturation, r.threshold_density, r.threshold_density_se, cfg.path_m, r.penetration_power,
                r.penetration_power_se, r.engine_unit_factor);
    std::printf("wrote %s%s%s (%zu frames, %.1f s)\n", a.out.c_str(), a.plot.empty() ? "" : " and ", a.plot.c_str(),
                cfg.densities.size(), r.seconds);
    return 0;
}

// ---- saturation ----

struct Patch {
    std::string name;
    std::vector<std::pair<double, double>> polygon;  // pixel coordinates
};

bool insidePolygon(const std::vector<std::pair<double, double>>& p, double x, double y)
{
    bool in = false;
    for (size_t i = 0, j = p.size() - 1; i < p.size(); j = i++)
        if ((p[i].second > y) != (p[j].second > y) &&
            x < (p[j].first - p[i].first) * (y - p[i].second) / (p[j].second - p[i].second) + p[i].first)
            in = !in;
    return in;
}

Patch parsePatch(const std::string& spec, bool rect)
{
    const auto eq = spec.find('=');
    const std::string opt = rect ? "--rect" : "--polygon";
    if (eq == std::string::npos || eq == 0) throw Error(opt, "expects NAME=numbers, got '" + spec + "'");
    Patch p;
    p.name = spec.substr(0, eq);
    const auto v = parseList(spec.substr(eq + 1), opt);
    if (rect) {
        if (v.size() != 4 || v[2] <= 0 || v[3] <= 0) throw Error(opt, "expects NAME=x,y,width,height with a positive size");
        p.polygon = {{v[0], v[1]}, {v[0] + v[2], v[1]}, {v[0] + v[2], v[1] + v[3]}, {v[0], v[1] + v[3]}};
    } else {
        if (v.size() < 6 || v.size() % 2) throw Error(opt, "expects NAME=x1,y1,x2,y2,x3,y3,... (at least 3 points)");
        for (size_t i = 0; i < v.size(); i += 2) p.polygon.emplace_back(v[i], v[i + 1]);
    }
    return p;
}

std::vector<std::string> framesOf(const std::vector<std::string>& inputs)
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
            out.push_back(in);
        }
    }
    return out;
}

/// Time of a frame from the last number in its file name (÷ fps when given).
double timeFromName(const std::string& path, double fps)
{
    const std::string stem = fs::path(path).stem().string();
    static const std::regex num(R"(\d+(\.\d+)?)");
    std::string last;
    for (auto it = std::sregex_iterator(stem.begin(), stem.end(), num); it != std::sregex_iterator(); ++it) last = it->str();
    if (last.empty()) throw Error(path, "has no number in its name to take the time from (use --timestamps)");
    const double v = std::stod(last);
    return fps > 0 ? v / fps : v;
}

std::vector<double> readTimestamps(const std::string& path, const std::vector<std::string>& frames)
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
        if (end == t.c_str() || !std::isfinite(v)) {
            if (ln == 1) continue;  // a header
            throw Error(path + ":" + std::to_string(ln), "time is not a finite number: '" + t + "'");
        }
        if (comma == std::string::npos) in_order.push_back(v);
        else by_name[fs::path(line.substr(0, comma)).filename().string()] = v;
    }
    std::vector<double> out;
    for (size_t i = 0; i < frames.size(); ++i) {
        const auto it = by_name.find(fs::path(frames[i]).filename().string());
        if (it != by_name.end()) out.push_back(it->second);
        else if (i < in_order.size()) out.push_back(in_order[i]);
        else throw Error(path, "has no time for " + frames[i]);
    }
    return out;
}

struct SatArgs {
    std::vector<std::string> inputs, rects, polygons;
    std::string out, ids, scene, timestamps, prefix = "target_";
    double fps = 0;
};

int runSaturation(const SatArgs& a)
{
    std::vector<Patch> patches;
    for (const auto& r : a.rects) patches.push_back(parsePatch(r, true));
    for (const auto& p : a.polygons) patches.push_back(parsePatch(p, false));
    for (size_t i = 0; i < patches.size(); ++i)
        for (size_t j = 0; j < i; ++j)
            if (patches[i].name == patches[j].name) throw Error("--rect/--polygon", "patch '" + patches[i].name + "' is named twice");
    if (patches.empty() && a.ids.empty()) throw Error("saturation", "give the target region: --rect/--polygon, or --ids with --scene");
    if (!a.ids.empty() && a.scene.empty()) throw Error("--ids", "needs --scene to name the objects");
    const auto frames = framesOf(a.inputs);
    RunFiles files;
    for (const auto& f : frames) files.input(f, "the frames");
    if (!a.ids.empty())
        for (const auto& f : framesOf({a.ids})) files.input(f, "--ids");
    files.input(a.scene, "--scene");
    files.input(a.timestamps, "--timestamps");
    files.output(a.out, "--out");
    std::vector<std::string> id_frames;
    TargetPatches target;  // from the object ids, with --ids
    if (!a.ids.empty()) {
        id_frames = framesOf({a.ids});
        if (id_frames.size() != frames.size())
            throw Error(a.ids, "holds " + std::to_string(id_frames.size()) + " id images for " + std::to_string(frames.size()) + " frames");
        target = targetPatches(loadScene(a.scene), a.prefix);
    }
    const auto times = a.timestamps.empty() ? std::vector<double>{} : readTimestamps(a.timestamps, frames);
    std::vector<std::string> names;
    for (const auto& p : patches) names.push_back(p.name);
    for (const auto& n : target.names)
        if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
    AtomicFile f(files.stage(a.out));
    std::ostream& o = f.stream();
    o << "time_s,saturation,saturation_median,saturation_sd,pixels";
    for (const auto& n : names) o << ',' << n << ',' << n << "_median," << n << "_sd";
    o << '\n';
    for (size_t k = 0; k < frames.size(); ++k) {
        const Image img = readImage(frames[k]);
        if (img.channels < 3) throw Error(frames[k], "is not an RGB image");
        Image ids;
        int object_ch = 0;
        if (!id_frames.empty()) {
            ids = readImage(id_frames[k]);
            if (ids.width != img.width || ids.height != img.height) throw Error(id_frames[k], "size differs from " + frames[k]);
            object_ch = ids.channel("object", 0);
        }
        // EXR frames hold linear radiance: encode them as a camera would before measuring.
        Image disp = img;
        if (fs::path(frames[k]).extension() == ".exr")
            for (float& v : disp.data) v = float(std::pow(std::clamp(double(v), 0.0, 1.0), 1 / 2.2));
        // Each pixel's patch (index into names, −1: none), found once per frame.
        std::vector<int> label(size_t(img.width) * img.height, -1);
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) {
                std::string n;
                for (const auto& p : patches)
                    if (insidePolygon(p.polygon, x + 0.5, y + 0.5)) {
                        n = p.name;
                        break;
                    }
                if (n.empty() && !id_frames.empty()) {
                    const int p = target.of(int(ids.at(x, y, object_ch)));
                    if (p >= 0) n = target.names[size_t(p)];
                }
                if (!n.empty()) label[size_t(y) * img.width + x] = int(std::find(names.begin(), names.end(), n) - names.begin());
            }
        auto labelAt = [&](int x, int y) { return label[size_t(y) * img.width + x]; };
        const auto all = maskedSaturation(disp, [&](int x, int y) { return labelAt(x, y) >= 0; });
        if (all.pixels == 0) throw Error(frames[k], "the target region holds no pixels");
        const double t = times.empty() ? timeFromName(frames[k], a.fps) : times[k];
        o << t << ',' << all.mean << ',' << all.median << ',' << all.stddev << ',' << all.pixels;
        for (size_t i = 0; i < names.size(); ++i) {
            const auto s = maskedSaturation(disp, [&](int x, int y) { return labelAt(x, y) == int(i); });
            if (s.pixels > 0) o << ',' << s.mean << ',' << s.median << ',' << s.stddev;
            else o << ",,,";
        }
        o << '\n';
    }
    f.commit();
    files.commit();
    std::printf("wrote %s (%zu frames, patches: %zu)\n", a.out.c_str(), frames.size(), names.size());
    return 0;
}

}  // namespace

void addCalibration(CLI::App& app, Runner& run)
{
    auto a = std::make_shared<CalibArgs>();
    auto* c = app.add_subcommand("calibrate", "Density ↔ saturation calibration (the paper's Fig. 7) from rendered frames, fitted with Ceres");
    c->add_option("scene", a->scene, "Built-in scene name or scene file")->capture_default_str();
    c->add_option("--densities", a->densities, "Comma-separated densities (default: 14 from 0 to 0.012)");
    c->add_option("--spp", a->cfg.spp, "Samples per pixel")->capture_default_str()->check(intRange(1, limits::kSpp));
    c->add_option("--width", a->cfg.width, "Frame width [px]")->capture_default_str()->check(intRange(1, limits::kFrameSide));
    c->add_option("--height", a->cfg.height, "Frame height [px]")->capture_default_str()->check(intRange(1, limits::kFrameSide));
    c->add_option("--seed", a->cfg.seed, "Render seed")->capture_default_str();
    c->add_option("--camera", a->cfg.camera, "Scene camera (default: the first)");
    c->add_option("--target-prefix", a->cfg.target_prefix, "Surface-name prefix of the target's patches")->capture_default_str();
    addChoice(c, "--loss", a->cfg.fit.loss, {{"none", RobustLoss::None}, {"huber", RobustLoss::Huber}, {"cauchy", RobustLoss::Cauchy}},
              "Robust loss of the curve fit, default huber");
    c->add_option("--out", a->out, "Calibration JSON to write (e.g. calib/bocas.json)")->required();
    c->add_option("--plot", a->plot, "Also write the plot (PNG)");
    c->callback([a, &run] { run = [a] { return runCalibrate(*a); }; });

    auto s = std::make_shared<SatArgs>();
    auto* t = app.add_subcommand("saturation", "Target HSV saturation of camera frames (files or a folder) → CSV");
    t->add_option("inputs", s->inputs, "Image files or a folder of frames")->required();
    t->add_option("--out", s->out, "CSV to write: time_s,saturation,... per-patch columns")->required();
    t->add_option("--rect", s->rects, "A patch: NAME=x,y,width,height in pixels (repeatable)");
    t->add_option("--polygon", s->polygons, "A patch: NAME=x1,y1,x2,y2,x3,y3,... in pixels (repeatable)");
    t->add_option("--ids", s->ids, "Id AOV image(s) from `smokescan render --ids` (file or folder, one per frame)");
    t->add_option("--scene", s->scene, "Scene whose surfaces the ids name");
    t->add_option("--target-prefix", s->prefix, "Surface-name prefix of the target's patches")->capture_default_str();
    t->add_option("--timestamps", s->timestamps, "Times: lines 'file,time_s' or one time per frame in name order");
    t->add_option("--fps", s->fps, "Frame rate: the number in a file name is a frame index")->check(positive());
    t->callback([s, &run] { run = [s] { return runSaturation(*s); }; });
}

}  // namespace smokescan::cli
