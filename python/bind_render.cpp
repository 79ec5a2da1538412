// smokescan.render: one camera frame through the smoke as numpy arrays (pipeline/render_run.hpp).
#include <pybind11/stl.h>

#include <memory>
#include <optional>

#include "module_support.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/pipeline/render_run.hpp"

namespace smokescan::python {
namespace {

/// One channel of an image as an H × W array of T.
template <class T>
py::array_t<T> channelArray(const Image& img, int c)
{
    std::vector<T> v(size_t(img.width) * size_t(img.height));
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) v[size_t(y) * size_t(img.width) + size_t(x)] = T(img.at(x, y, c));
    return ownedArray(std::move(v)).reshape({py::ssize_t(img.height), py::ssize_t(img.width)});
}

py::dict frameDict(RenderedFrame&& f, double time_s)
{
    py::dict d;
    d["time_s"] = time_s;
    d["camera"] = f.camera.name;
    d["exposure"] = f.exposure;
    d["samples"] = f.result.samples;
    d["seconds"] = f.result.seconds;
    d["object_id"] = channelArray<int32_t>(f.result.ids, 0);
    d["material_id"] = channelArray<int32_t>(f.result.ids, 1);
    d["depth_m"] = channelArray<float>(f.result.ids, 2);
    d["radiance"] = imageArray(std::move(f.result.radiance));
    d["variance"] = imageArray(std::move(f.result.variance));
    d["display"] = imageArray(std::move(f.display));
    return d;
}

}  // namespace

void bindRender(py::module_& m)
{
    m.def(
        "render",
        [](std::shared_ptr<Scene> scene, double time_s, const std::string& camera, long long width, long long height,
           long long spp, py::object seed, long long max_depth, std::optional<double> exposure, py::object progress) {
            RenderRunConfig cfg;
            cfg.render.time_s = finiteArg(time_s, "--time");
            cfg.render.camera = camera;
            if (width < 0 || width > limits::kFrameSide || height < 0 || height > limits::kFrameSide)
                throw Error(width < 0 || width > limits::kFrameSide ? "--width" : "--height",
                            "must lie in 1…" + std::to_string(limits::kFrameSide) + " px (0: the camera's)");
            cfg.render.width = int(width);
            cfg.render.height = int(height);
            if (spp < 1 || spp > limits::kSpp) throw Error("--spp", "must lie in 1…" + std::to_string(limits::kSpp));
            cfg.render.spp = int(spp);
            cfg.render.seed = seedArg(seed);
            if (max_depth < 0 || max_depth > limits::kPathDepth)
                throw Error("--max-depth", "must lie in 0…" + std::to_string(limits::kPathDepth));
            cfg.render.max_depth = int(max_depth);
            cfg.render.progress = false;
            if (exposure && !(*exposure > 0 && *exposure <= 1e6))
                throw Error("--exposure", "must be a number in (0, 1e6], or None for auto");
            cfg.exposure = exposure.value_or(0.0);
            PyControl pc(std::move(progress));
            RenderedFrame f = released(pc, [&](const RunControl& c) {
                const SurfaceSet surfaces(*scene);
                return renderFrame(*scene, surfaces, cfg, c);
            });
            return frameDict(std::move(f), cfg.render.time_s);
        },
        py::arg("scene").none(false), py::arg("time_s") = 0.0, py::arg("camera") = "", py::arg("width") = 0,
        py::arg("height") = 0, py::arg("spp") = 16, py::arg("seed") = 1, py::arg("max_depth") = 256,
        py::arg("exposure") = py::none(), py::arg("progress") = py::none(),
        "One frame of a scene camera (default: the first) at time_s through the smoke, as `smokescan render` "
        "makes it: a dict of H×W×3 float32 arrays (radiance [W/(m²·sr)] and its variance; display, sRGB-encoded "
        "in [0, 1] at the exposure used) and H×W arrays (object_id, material_id: −1 for none; depth_m: inf for "
        "none). progress(done, total) counts 16×16-pixel tiles");
}

}  // namespace smokescan::python
