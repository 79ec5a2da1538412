#include "smokescan/pipeline/render_run.hpp"

#include <memory>
#include <utility>

#include "smokescan/render/camera.hpp"
#include "watched.hpp"

namespace smokescan {
namespace {

/// The render on a thread of its own while this one reports progress and asks to cancel.
RenderResult watchedRender(const Scene& scene, const SurfaceSet& surfaces, RenderConfig cfg, const RunControl& control)
{
    RenderWatch watch;
    cfg.watch = &watch;
    cfg.progress = false;
    return detail::runWatched<RenderResult>(
        [&] { return render(scene, surfaces, cfg); }, watch,
        [&] { return std::pair<long long, long long>(watch.tiles_done, watch.tiles_total); }, control);
}

}  // namespace

RenderedFrame renderFrame(const Scene& scene, const SurfaceSet& surfaces, const RenderRunConfig& cfg,
                          const RunControl& control)
{
    checkCancel(control);
    RenderedFrame f;
    f.result = control.cancel || control.progress ? watchedRender(scene, surfaces, cfg.render, control)
                                                  : render(scene, surfaces, cfg.render);
    // render found the camera; an omni camera meters over its mirror disc (the frame around it is black).
    const Camera* cam = scene.findCamera(cfg.render.camera);
    f.camera = scene.cameraAt(*cam, cfg.render.time_s);
    if (cfg.render.width > 0) f.camera.width = cfg.render.width;
    if (cfg.render.height > 0) f.camera.height = cfg.render.height;
    const auto omni = f.camera.kind == CameraKind::Omni ? makeCamera(f.camera) : nullptr;
    f.display = toDisplay(f.result.radiance, cfg.exposure, &f.exposure, omni.get());
    return f;
}

}  // namespace smokescan
