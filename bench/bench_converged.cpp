// One converged BOCAS 640×480 frame at the threshold density 0.0028, as `calibrate` measures it
// (the target's radiance in batches until 3 % relative error, through the scene camera's sensor
// model): seconds per frame and the target's mean saturation, beside a reference of the same frame
// at many more samples per target pixel (default 1024: 128 batches of 8; about 15 minutes on 2 cores).
// Usage: smokescan_bench_converged [reference_spp (0: skip)]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "smokescan/calib/calibration.hpp"
#include "smokescan/camera/saturation_render.hpp"
#include "smokescan/render/renderer.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/scene/surfaces.hpp"

using namespace smokescan;

namespace {

void run(const Scene& scene, const SurfaceSet& set, const TargetRadianceConfig& field, const char* what, uint64_t seed)
{
    RenderConfig rc;
    rc.width = 640;
    rc.height = 480;
    rc.seed = seed;  // the reference's own: no metering frame, camera noise or batch shared with the default
    rc.progress = false;
    const auto t0 = std::chrono::steady_clock::now();
    const TargetSaturation m = measureConvergedSaturation(scene, set, rc, "target_", field);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%-10s %5d spp per target pixel: %7.1f s, target mean saturation %.4f ± %.4f (relative error %.3f)\n",
                what, m.spp, s, m.all.mean, m.se, m.rel_error);
    std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv)
{
    const int ref_spp = std::clamp(argc > 1 ? std::atoi(argv[1]) : 1024, 0, 2048);  // 2 GiB of batches
    const Scene scene = uniformSmokeScene(loadScene("bocas"), 0.0028);
    const SurfaceSet set(scene);
    run(scene, set, TargetRadianceConfig{}, "default", 7);
    if (ref_spp <= 0) return 0;
    TargetRadianceConfig ref;
    ref.min_batches = ref.max_batches = std::max(4, ref_spp / ref.batch_spp);
    ref.rel_error = 1e-9;
    run(scene, set, ref, "reference", 1007);
    return 0;
}
