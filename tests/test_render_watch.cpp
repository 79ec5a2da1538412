// A render watched and stopped from another thread (render/renderer.hpp: RenderWatch), and the
// pipeline's frame and calibration calls stopped by their control (pipeline/render_run.hpp,
// calibrate_run.hpp).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "smokescan/pipeline/calibrate_run.hpp"
#include "smokescan/pipeline/render_run.hpp"
#include "smokescan/scene/scene_io.hpp"

using namespace smokescan;

namespace {

RenderConfig smallFrame(int w, int h, int spp)
{
    RenderConfig c;
    c.time_s = 60;
    c.width = w;
    c.height = h;
    c.spp = spp;
    c.progress = false;
    return c;
}

}  // namespace

TEST(RenderWatch, CountsEveryTileAndAStopBeforeTheStartRendersNone)
{
    const Scene scene = loadScene("bocas");
    const SurfaceSet surfaces(scene);
    RenderWatch watch;
    RenderConfig cfg = smallFrame(100, 70, 1);  // 7 × 5 tiles of 16 px
    cfg.watch = &watch;
    const RenderResult whole = render(scene, surfaces, cfg);
    EXPECT_FALSE(whole.stopped);
    EXPECT_EQ(watch.tiles_total, 35);
    EXPECT_EQ(watch.tiles_done, 35);
    RenderWatch stopped;
    stopped.stop = true;
    cfg.watch = &stopped;
    const RenderResult none = render(scene, surfaces, cfg);
    EXPECT_TRUE(none.stopped);
    EXPECT_EQ(stopped.tiles_done, 0);
    for (float v : none.radiance.data) ASSERT_EQ(v, 0.0f);
}

TEST(RenderWatch, AStopFromAnotherThreadEndsTheFrameEarly)
{
    const Scene scene = loadScene("bocas");
    const SurfaceSet surfaces(scene);
    RenderWatch watch;
    RenderConfig cfg = smallFrame(320, 240, 4096);  // minutes of work, seconds a tile
    cfg.watch = &watch;
    std::thread stopper([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        watch.stop = true;
    });
    const auto t0 = std::chrono::steady_clock::now();
    const RenderResult r = render(scene, surfaces, cfg);
    stopper.join();
    EXPECT_TRUE(r.stopped);
    EXPECT_LT(watch.tiles_done, watch.tiles_total);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
}

TEST(RenderWatch, AStopEndsTheFrameWithinAPixelNotATile)
{
    // One tile of 16 × 16 px at 4096 samples a pixel in smoke (15 s of work here, 45 s with the
    // sanitizers; a pixel 60 to 170 ms): a stop after 1.5 s leaves the tile unfinished, some
    // pixels rendered and the rest not, the ids all made. (200 ms was too short for a sanitized
    // build beside another test: no pixel done.)
    const Scene scene = loadScene("bocas");
    const SurfaceSet surfaces(scene);
    RenderWatch watch;
    RenderConfig cfg = smallFrame(16, 16, 4096);
    cfg.watch = &watch;
    std::thread stopper([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(1500));
        watch.stop = true;
    });
    const RenderResult r = render(scene, surfaces, cfg);
    stopper.join();
    EXPECT_TRUE(r.stopped);
    EXPECT_EQ(watch.tiles_total, 1);
    EXPECT_EQ(watch.tiles_done, 0);
    int lit = 0, dark = 0;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            (r.radiance.at(x, y, 0) + r.radiance.at(x, y, 1) + r.radiance.at(x, y, 2) > 0 ? lit : dark)++;
            ASSERT_GE(r.ids.at(x, y, 0), 0.0f) << "an id is made for every pixel";
        }
    EXPECT_GT(lit, 0);
    EXPECT_GT(dark, 0);
}

TEST(RenderWatch, ThePipelinesFrameIsTheRendersAndItsControlStopsIt)
{
    const Scene scene = loadScene("bocas");
    const SurfaceSet surfaces(scene);
    RenderRunConfig cfg;
    cfg.render = smallFrame(48, 32, 2);
    // Watched (a control given) or not, the same frame; progress ends at the tile count.
    long long last_done = -1, last_total = -1;
    RunControl watching;
    watching.progress = [&](long long d, long long t) { last_done = d, last_total = t; };
    const RenderedFrame a = renderFrame(scene, surfaces, cfg, watching);
    const RenderedFrame b = renderFrame(scene, surfaces, cfg);
    EXPECT_EQ(a.result.radiance.data, b.result.radiance.data);
    EXPECT_EQ(a.display.data, b.display.data);
    EXPECT_EQ(last_done, 6);
    EXPECT_EQ(last_total, 6);
    // A cancel during a long frame: Cancelled, soon.
    cfg.render = smallFrame(320, 240, 4096);
    RunControl stop;
    const auto t0 = std::chrono::steady_clock::now();
    stop.cancel = [&] { return std::chrono::steady_clock::now() - t0 > std::chrono::milliseconds(200); };
    EXPECT_THROW(renderFrame(scene, surfaces, cfg, stop), Cancelled);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
}

TEST(RenderWatch, ACalibrationIsStoppedWithinAFrame)
{
    const Scene scene = loadScene("bocas");
    CalibrateConfig cfg;
    cfg.width = 640;
    cfg.height = 480;
    cfg.field.batch_spp = 64;  // a frame takes far longer than the test allows
    RunControl stop;
    const auto t0 = std::chrono::steady_clock::now();
    stop.cancel = [&] { return std::chrono::steady_clock::now() - t0 > std::chrono::milliseconds(300); };
    EXPECT_THROW(runCalibration(scene, cfg, stop), Cancelled);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 10.0);
}
