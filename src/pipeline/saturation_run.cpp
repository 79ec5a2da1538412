#include "smokescan/pipeline/saturation_run.hpp"

#include <cmath>
#include <optional>

#include "smokescan/camera/frame_saturation.hpp"
#include "smokescan/camera/target_patches.hpp"
#include "smokescan/fit/bag_saturation.hpp"
#include "smokescan/scene/scene_io.hpp"

namespace smokescan {
namespace {

SaturationSeries bagSaturation(const SaturationRunConfig& a, const FrameRegions& regions, const RunControl& control)
{
    if (!a.inputs.empty()) throw Error("--bag", "is in place of the frame files; give one of them");
    for (const auto& [given, option] :
         {std::pair{!a.ids.empty(), "--ids"}, std::pair{!a.scene.empty(), "--scene"},
          std::pair{!a.timestamps.empty(), "--timestamps"}, std::pair{a.fps > 0, "--fps"}})
        if (given) throw Error(option, "goes with frame files; a bag's frames carry their stamps");
    checkCancel(control);
    // A bag's frame count is known only at its end: progress counts frames of an unknown total (0).
    return measureBagSaturation(a.bag, a.topic, regions, [&](long long done) {
        reportProgress(control, done, 0);
        checkCancel(control);
    });
}

}  // namespace

SaturationSeries runSaturation(const SaturationRunConfig& a, const RunControl& control)
{
    if (!(a.fps == 0 || (a.fps >= 1e-6 && a.fps <= 1e6)))
        throw Error("--fps", "must lie in [1e-6, 1e6] Hz (0: the number in a frame's name is its time [s])");
    if (a.fps > 0 && !a.timestamps.empty()) throw Error("--fps", "or --timestamps: give one of them");
    FrameRegions regions = frameRegions(a.rects, a.polygons);
    if (!a.bag.empty()) return bagSaturation(a, regions, control);
    if (!a.topic.empty()) throw Error("--topic", "names a bag's topic; give --bag");
    if (a.inputs.empty()) throw Error("saturation", "give the frames: image files, a folder, or --bag PATH");
    if (regions.patches.empty() && a.ids.empty())
        throw Error("saturation", "give the target region: --rect/--polygon, or --ids with --scene");
    if (!a.ids.empty() && a.scene.empty()) throw Error("--ids", "needs --scene to name the objects");
    if (a.target_prefix.empty()) throw Error("--target-prefix", "must not be empty");
    const auto frames = listFrames(a.inputs);
    const auto id_frames = a.ids.empty() ? std::vector<std::string>{} : listFrames({a.ids});
    std::optional<Scene> scene;
    if (!a.scene.empty()) {
        scene = loadScene(a.scene);
        if (a.on_scene) a.on_scene(*scene);
    }
    if (!a.ids.empty()) {
        if (id_frames.size() != frames.size())
            throw Error(a.ids,
                        "holds " + std::to_string(id_frames.size()) + " id images for " +
                            std::to_string(frames.size()) + " frames");
        regions.target = targetPatches(*scene, a.target_prefix);
        regions.by_id = true;
    }
    const std::vector<double> stamps =
        a.timestamps.empty() ? std::vector<double>{} : readFrameTimestamps(a.timestamps, frames);
    const long long n = (long long)frames.size();
    checkCancel(control);
    // A frame's time is asked once it has been read: its progress, and the cancel before the next.
    return measureFrames(
        frames, id_frames,
        [&](size_t k) {
            const double t = stamps.empty() ? frameTimeFromName(frames[k], a.fps) : stamps[k];
            reportProgress(control, (long long)k + 1, n);
            if ((long long)k + 1 < n) checkCancel(control);
            return t;
        },
        regions);
}

}  // namespace smokescan
