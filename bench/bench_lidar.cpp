// Lidar throughput (docs/performance.md, "3D lidar"): frames of a spinning lidar in the plume scene
// (its clouds at t = 20 s), physical model, on every core, beside two yardsticks on the same beams
// in the same run:
//  - Embree alone: each beam's central ray to its first surface, the floor any lidar simulation
//    pays;
//  - OpenVDB alone: each beam's optical depth up to that surface through OpenVDB's own ray tools,
//    a VolumeRayIntersector (hierarchical DDA over the tree's active nodes) per grid and, inside
//    each active span, a voxel DDA summing density × length exactly (box filtering).
// Then how the cost grows with columns, channels and smoke. Medians of 3 repetitions.
#include <openvdb/math/DDA.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/RayIntersector.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>
#include <thread>

#include "../src/media/vdb_grid.hpp"
#include "smokescan/lidar/lidar_scanner.hpp"
#include "smokescan/scene/scene_io.hpp"

using namespace smokescan;

namespace {

using Clock = std::chrono::steady_clock;

/// The fastest of the last medianSeconds() runs [s]: on a shared machine, the least disturbed.
double g_fastest_s = 0;

/// The median over `reps` runs of f's wall time [s].
double medianSeconds(int reps, const std::function<void()>& f)
{
    std::vector<double> t;
    for (int i = 0; i < reps; ++i) {
        const auto t0 = Clock::now();
        f();
        t.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    }
    std::sort(t.begin(), t.end());
    g_fastest_s = t.front();
    return t[t.size() / 2];
}

/// Every beam of one frame as a world ray from the frame's start pose (the sensor stands still).
std::vector<Ray> frameRays(const Scene& scene, const SensorMount& mount, const LidarSpec& spec)
{
    const Pose pose = scene.sensorAt(mount, 0).pose;
    std::vector<Ray> rays;
    for (const PatternBeam& b : framePattern(spec)) {
        const double ce = std::cos(b.elevation_rad);
        const Vec3 local(ce * std::cos(b.azimuth_rad), ce * std::sin(b.azimuth_rad), std::sin(b.elevation_rad));
        rays.push_back(Ray{pose.t, pose.rotate(local).normalized()});
    }
    return rays;
}

/// ∫ρ ds [density·m] of one grid along a world ray over [0, t_max] world metres, by OpenVDB's ray
/// tools: the intersector's active spans, a voxel DDA inside each.
using VdbRay = openvdb::math::Ray<double>;
using Intersector = openvdb::tools::VolumeRayIntersector<openvdb::FloatGrid>;

double vdbColumn(Intersector& inter, const openvdb::FloatGrid& grid, const Ray& ray, double t_max)
{
    // The index ray, shifted by half a voxel so that the DDA's cell [i, i+1) is the voxel centred
    // on i (box filtering, as smokescan's own walk).
    const openvdb::Vec3d o = grid.worldToIndex(openvdb::Vec3d(ray.o.x(), ray.o.y(), ray.o.z())) + openvdb::Vec3d(0.5);
    const openvdb::Vec3d e =
        grid.worldToIndex(openvdb::Vec3d(ray.o.x() + ray.d.x(), ray.o.y() + ray.d.y(), ray.o.z() + ray.d.z())) +
        openvdb::Vec3d(0.5);
    const openvdb::Vec3d d = e - o;  // one world metre in index units
    const double scale = d.length();
    VdbRay iray(o, d / scale, 0, t_max * scale);
    if (!inter.setIndexRay(iray)) return 0;
    auto acc = grid.getConstAccessor();
    double sum = 0, t0, t1;
    while (inter.march(t0, t1)) {
        openvdb::math::DDA<VdbRay, 0> dda(iray, t0, t1);
        do {
            const double a = dda.time(), b = dda.next();
            sum += double(acc.getValue(dda.voxel())) * (b - a);
        } while (dda.step());
    }
    return sum / scale;
}

struct Row {
    const char* what;
    long long beams;
    double seconds;
};

void print(const Row& r, double realtime_beams_s)
{
    const double rate = double(r.beams) / r.seconds;
    std::printf("| %s | %lld | %.3f | %.2f M | %.2f× |\n", r.what, r.beams, r.seconds, rate / 1e6,
                rate / realtime_beams_s);
}

}  // namespace

int main(int argc, char** argv)
{
    // smokescan_bench_lidar [REPS] [--frame-only]: --frame-only runs the headline frame alone (to profile it).
    const int reps = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
    const bool frame_only = argc > 2 && std::string(argv[2]) == "--frame-only";
    openvdb::initialize();
    Scene scene = loadScene("plume");
    const SurfaceSet surfaces(scene);
    const SensorMount mount = defaultLidarMount(scene, "lidar");
    const double t = 20;
    std::printf("threads: %u; plume scene at t = %g s; medians of %d\n\n", std::thread::hardware_concurrency(), t,
                reps);
    std::printf("| case | beams a frame | s a frame | beams/s | of the sensor's real time |\n|---|---|---|---|---|\n");

    auto frameRow = [&](const char* what, const Scene& sc, const SurfaceSet& sf, const std::string& preset, int columns,
                        ReturnMode mode) {
        LidarSpec spec = lidarSpec(preset);
        configureLidar(spec, spec.rate_hz, columns, "bench", "bench");
        const LidarScanner scanner(sc, sf, mount, spec, mode, 1);
        const long long beams = (long long)framePattern(spec).size();
        scanner.frame(t, 0);  // warm
        const double s = medianSeconds(reps, [&] { scanner.frame(t, 1); });
        print({what, beams, s}, double(beams) * spec.rate_hz);
        return s;
    };
    const double os1_s =
        frameRow("OS1-128, 1024 × 10 Hz, dual, physical model", scene, surfaces, "os1-128", 1024, ReturnMode::Dual);
    if (frame_only) {
        std::printf("\nthe fastest of the %d frames: %.4f s\n", reps, g_fastest_s);
        return 0;
    }

    // The yardsticks on the same beams.
    LidarSpec os1 = lidarSpec("os1-128");
    const std::vector<Ray> rays = frameRays(scene, mount, os1);
    const long long n = (long long)rays.size();
    std::vector<double> hit(rays.size());
    const double embree_s = medianSeconds(reps, [&] {
        tbb::parallel_for(size_t(0), rays.size(), [&](size_t i) {
            hit[i] = surfaces.closest(rays[i], os1.range_max_m + 1).endOr(os1.range_max_m + 1);
        });
    });
    print({"yardstick: Embree, the central ray to its first surface", n, embree_s}, double(n) * 10);
    const SmokeField field = SmokeField::at(scene.volumes, t);
    std::vector<std::unique_ptr<Intersector>> masters;
    std::vector<const openvdb::FloatGrid*> grids;
    for (const SmokeField::Entry& e : field.entries()) {
        const openvdb::FloatGrid& g = *e.grid->impl().grid;
        if (g.activeVoxelCount() == 0) continue;
        masters.push_back(std::make_unique<Intersector>(g));
        grids.push_back(&g);
    }
    std::vector<double> column(rays.size());
    const double vdb_s = medianSeconds(reps, [&] {
        tbb::enumerable_thread_specific<std::vector<Intersector>> local([&] {
            std::vector<Intersector> v;
            for (const auto& m : masters) v.emplace_back(*m);  // shallow copies for this thread
            return v;
        });
        tbb::parallel_for(size_t(0), rays.size(), [&](size_t i) {
            std::vector<Intersector>& mine = local.local();
            double c = 0;
            for (size_t g = 0; g < grids.size(); ++g) c += vdbColumn(mine[g], *grids[g], rays[i], hit[i]);
            column[i] = c;
        });
    });
    print({"yardstick: OpenVDB ray tools, each beam's column up to its surface", n, vdb_s}, double(n) * 10);
    // The same columns by smokescan's own walk, to show the yardstick integrates the same smoke.
    double ours = 0, theirs = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const BeamSmoke b = field.trace(rays[i], 0, hit[i], BeamQuery{});
        ours += b.column_regional + b.column_local;
        theirs += column[i];
    }
    std::printf("\nmean column a beam [density·m]: smokescan %.6g, OpenVDB ray tools %.6g\n", ours / double(n),
                theirs / double(n));
    std::printf("the frame against the yardsticks: %.1f× Embree's time, %.1f× OpenVDB's\n\n", os1_s / embree_s,
                os1_s / vdb_s);

    std::printf("| case | beams a frame | s a frame | beams/s | of the sensor's real time |\n|---|---|---|---|---|\n");
    frameRow("OS1-128, 512 × 10 Hz, dual", scene, surfaces, "os1-128", 512, ReturnMode::Dual);
    frameRow("OS1-128, 2048 × 10 Hz, dual", scene, surfaces, "os1-128", 2048, ReturnMode::Dual);
    frameRow("OS1-128, 1024 × 10 Hz, strongest", scene, surfaces, "os1-128", 1024, ReturnMode::Strongest);
    frameRow("VLP-16, 10 Hz, dual", scene, surfaces, "vlp16", 0, ReturnMode::Dual);
    frameRow("HDL-32E, 10 Hz, dual", scene, surfaces, "hdl32e", 0, ReturnMode::Dual);
    Scene clear = scene;
    clear.volumes.clear();
    const SurfaceSet clear_surfaces(clear);
    frameRow("OS1-128, 1024 × 10 Hz, dual, no smoke", clear, clear_surfaces, "os1-128", 1024, ReturnMode::Dual);
    Scene dense = scene;
    for (SmokeVolume& v : dense.volumes) {
        v.medium.sigma_t_785 *= 4;
        v.medium.sigma_t_905 *= 4;
    }
    const SurfaceSet dense_surfaces(dense);
    frameRow("OS1-128, 1024 × 10 Hz, dual, smoke 4× as thick", dense, dense_surfaces, "os1-128", 1024,
             ReturnMode::Dual);
    return 0;
}
