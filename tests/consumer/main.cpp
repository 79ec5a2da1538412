// Links the installed smokescan: one scan of the built-in bocas room, the URG's straight-ahead beam.
#include <cstdio>

#include "smokescan/core/version.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/scene/surfaces.hpp"
#include "smokescan/sensors/scanner.hpp"

int main()
{
    using namespace smokescan;
    const Scene scene = loadScene("bocas");
    const SurfaceSet surfaces(scene);
    ScanConfig cfg;
    cfg.sensor = "urg04lx";
    const Scanner scanner(scene, surfaces, cfg);
    const Scan scan = scanner.scanAt(0.0, 0);
    const size_t ahead = size_t(384 - 44);  // URG step 384 looks straight ahead
    std::printf("smokescan %s: %zu beams, ahead %lld mm\n", version(), scan.value.size(), scan.value[ahead]);
    return scan.value.size() == 682 && scan.value[ahead] > 20 ? 0 : 1;
}
