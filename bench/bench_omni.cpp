// The omnicam rangefinder's speed (docs/performance.md): one 1024×768 frame of the maze at 8 spp
// rendered and read, and the rangefinder alone on that frame, beside a yardstick in the same run:
// classifying every pixel of the frame with the same histogram (what a per-pixel free-space map
// costs; the scanlines touch only the pixels on their lines).
#include <benchmark/benchmark.h>

#include "smokescan/omni/omni_run.hpp"
#include "smokescan/scene/scene_io.hpp"

using namespace smokescan;

namespace {

struct Maze {
    Scene scene = loadScene("maze");
    SurfaceSet surfaces{scene};
    ColourHistogram hist;
    Image frame;
    std::unique_ptr<OmniRun> run;
    OmniRangeConfig cfg;
    Maze()
    {
        OmniRunConfig rc;
        rc.spp = 8;
        run = std::make_unique<OmniRun>(scene, surfaces, rc);
        run->train(hist, 0, 0);
        run->read(hist, 5, 1, &frame);
        cfg.height_m = 0.931;
    }
};

Maze& maze()
{
    static Maze m;
    return m;
}

void BM_RenderAndRange_1024x768_8spp(benchmark::State& st)
{
    Maze& m = maze();
    uint64_t k = 100;
    for (auto _ : st) benchmark::DoNotOptimize(m.run->read(m.hist, 5, k++));
}
BENCHMARK(BM_RenderAndRange_1024x768_8spp)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

void BM_RangefinderAlone(benchmark::State& st)
{
    Maze& m = maze();
    const OmniCamera& cam = m.run->cameraAt(5);
    for (auto _ : st) benchmark::DoNotOptimize(omniRange(m.frame, cam, m.hist, m.cfg));
    st.counters["scanlines/s"] = benchmark::Counter(360.0 * double(st.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RangefinderAlone)->Unit(benchmark::kMillisecond);

void BM_Yardstick_ClassifyEveryPixel(benchmark::State& st)
{
    Maze& m = maze();
    for (auto _ : st) {
        long long free = 0;
        for (int y = 0; y < m.frame.height; ++y)
            for (int x = 0; x < m.frame.width; ++x)
                free += m.hist.isFree(m.frame.at(x, y, 0), m.frame.at(x, y, 1), m.frame.at(x, y, 2), m.cfg.threshold);
        benchmark::DoNotOptimize(free);
    }
}
BENCHMARK(BM_Yardstick_ClassifyEveryPixel)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
