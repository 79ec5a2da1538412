// Variance per second of the renderer's estimators, where the calibration measures: camera rays
// through the centre of each BOCAS target patch, in the calibration's homogeneous smoke at the
// threshold density 0.0028 and at the densest 0.012. For each estimator (next-event estimation at
// collisions or in-scattered light per segment; plain or split camera ray) the relative variance
// of one sample, from the spread of independent batch means, and the time per sample; their
// product is the work-normalised variance (lower is better), relative to the plain estimator.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <tuple>
#include <vector>

#include "smokescan/calib/calibration.hpp"
#include "smokescan/render/renderer.hpp"
#include "smokescan/scene/mesh.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/scene/surfaces.hpp"

using namespace smokescan;

namespace {

/// One ray, as a 1×1 camera.
class OneRay final : public CameraModel {
public:
    explicit OneRay(const Ray& r) : r_(r) {}
    int width() const override { return 1; }
    int height() const override { return 1; }
    bool generateRay(double, double, Ray& ray) const override
    {
        ray = r_;
        return true;
    }

private:
    Ray r_;
};

struct Estimate {
    double rel_var = 0, us_per_sample = 0;
};

Estimate measure(const Scene& s, const SurfaceSet& set, const Ray& ray, bool segment, bool split, int batches, int spp)
{
    const OneRay cam(ray);
    std::vector<double> m;
    double secs = 0;
    for (int b = 0; b < batches; ++b) {
        RenderConfig c;
        c.spp = spp;
        c.seed = uint64_t(1000 + b);
        c.progress = false;
        c.segment_lighting = segment;
        c.split_primary = split;
        const auto t0 = std::chrono::steady_clock::now();
        const RenderResult r = render(s, set, cam, c);
        secs += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        m.push_back((r.radiance.at(0, 0, 0) + r.radiance.at(0, 0, 1) + r.radiance.at(0, 0, 2)) / 3);
    }
    double mean = 0, var = 0;
    for (double x : m) mean += x / m.size();
    for (double x : m) var += (x - mean) * (x - mean) / (m.size() - 1);
    return {var * spp / (mean * mean), secs / (double(batches) * spp) * 1e6};
}

}  // namespace

int main(int argc, char** argv)
{
    const int batches = argc > 1 ? std::atoi(argv[1]) : 32, spp = argc > 2 ? std::atoi(argv[2]) : 1024;
    const Scene bocas = loadScene("bocas");
    const Vec3 cam = bocas.cameras[0].pose.t;
    std::printf("estimator variance per second: %d batches of %d samples per ray (one thread)\n", batches, spp);
    std::printf(
        "| density | patch | estimator | relative variance per sample | µs per sample | variance × time, vs plain |\n");
    std::printf("|---|---|---|---|---|---|\n");
    for (double rho : {0.0028, 0.012}) {
        const Scene s = uniformSmokeScene(bocas, rho);
        const SurfaceSet set(s);
        for (const char* patch : {"target_blue", "target_yellow", "target_gold"}) {
            const Surface& t = s.surfaces[size_t(s.findSurface(patch))];
            Aabb box;
            for (const Vec3& p : tessellate(t).points_m) box.extend(p);
            const Ray ray{cam, (0.5 * (box.lo + box.hi) - cam).normalized()};
            double plain = 0;
            for (const auto& [seg, split, name] :
                 {std::tuple{false, false, "NEE at collisions (plain)"},
                  std::tuple{true, false, "per-segment in-scatter"}, std::tuple{false, true, "split camera ray"},
                  std::tuple{true, true, "both (default)"}}) {
                const Estimate e = measure(s, set, ray, seg, split, batches, spp);
                const double work = e.rel_var * e.us_per_sample;
                if (!seg && !split) plain = work;
                std::printf("| %.4f | %s | %s | %.2f | %.2f | %.2f |\n", rho, patch + 7, name, e.rel_var,
                            e.us_per_sample, work / plain);
            }
        }
    }
}
