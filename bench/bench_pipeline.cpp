// The library's runs alone (pipeline/), for the Python module's overhead (bench/bench_python.py
// runs this beside the same calls through Python): a 2D laser's scans and a 3D lidar's frames in
// the plume scene, kept in memory as the module keeps them. Prints "laser S" and "lidar S", the
// median wall time [s] of each over `reps` runs.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <vector>

#include "smokescan/pipeline/laser_run.hpp"
#include "smokescan/pipeline/lidar_run.hpp"
#include "smokescan/scene/scene_io.hpp"

using namespace smokescan;

namespace {

double medianSeconds(int reps, const std::function<void()>& f)
{
    std::vector<double> t;
    for (int i = 0; i < reps; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        f();
        t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
}

}  // namespace

int main(int argc, char** argv)
{
    const int reps = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
    const Scene scene = loadScene("plume");
    ScanConfig laser;  // bench_python.py: scan(scene, "lms200", t0=20, t1=30, rate_hz=10)
    laser.sensor = "lms200";
    laser.from_s = 20;
    laser.to_s = 30;
    laser.rate_hz = 10;
    laser.keep_beams = false;
    LidarRunConfig lidar;  // bench_python.py: scan_lidar(scene, "vlp16", returns="dual", t0=20, t1=21)
    lidar.returns = "dual";
    lidar.from_s = 20;
    lidar.to_s = 21;
    const double laser_s = medianSeconds(reps, [&] { LaserRun(scene, laser).collect(); });
    const double lidar_s = medianSeconds(reps, [&] { LidarRun(scene, lidar).collect(); });
    std::printf("laser %.6f\nlidar %.6f\n", laser_s, lidar_s);
    return 0;
}
