#include "smokescan/pipeline/render_run.hpp"

#include <chrono>
#include <exception>
#include <memory>
#include <thread>

#include "smokescan/render/camera.hpp"

namespace smokescan {
namespace {

/// The render on a thread of its own while this one reports progress and asks to cancel.
RenderResult watchedRender(const Scene& scene, const SurfaceSet& surfaces, RenderConfig cfg, const RunControl& control)
{
    RenderWatch watch;
    cfg.watch = &watch;
    cfg.progress = false;
    RenderResult r;
    std::exception_ptr failed;
    std::atomic<bool> finished{false};
    std::thread worker([&] {
        try {
            r = render(scene, surfaces, cfg);
        } catch (...) {
            failed = std::current_exception();
        }
        finished = true;
    });
    try {
        while (!finished) {
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
            if (control.cancel && control.cancel()) watch.stop = true;
            if (watch.stop) break;
            reportProgress(control, watch.tiles_done, watch.tiles_total);
        }
    } catch (...) {  // the control itself threw: the render stops, and its error goes on
        watch.stop = true;
        worker.join();
        throw;
    }
    worker.join();
    if (failed) std::rethrow_exception(failed);
    if (watch.stop || r.stopped) throw Cancelled();
    reportProgress(control, watch.tiles_done, watch.tiles_total);
    return r;
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
