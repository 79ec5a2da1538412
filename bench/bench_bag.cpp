// Bag throughput (issue 34): writing and reading a 6-minute 3 Hz URG-04LX run (1081 scans of
// bocas, as simulated) and an OS1-128 at 1024 × 10 Hz, dual return, in the plume (frames as
// simulated, repeated with new stamps to make the run's length), against the floor of copying a
// file of the same size (std::filesystem::copy_file, in the same run); and each bag's size
// against the text log or the PCD frames of the same data.
//   ./build/smokescan_bench_bag [os1 seconds (default 60)] [folder (default /tmp)]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "smokescan/bag/bag_input.hpp"
#include "smokescan/bag/mcap_reader.hpp"
#include "smokescan/bag/scan_bag.hpp"
#include "smokescan/lidar/lidar_scanner.hpp"
#include "smokescan/lidar/lidar_spec.hpp"
#include "smokescan/lidar/point_cloud_io.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/scene/surfaces.hpp"
#include "smokescan/sensors/laser_log.hpp"

using namespace smokescan;
namespace fs = std::filesystem;

namespace {

double since(std::chrono::steady_clock::time_point t0)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

uint64_t folderBytes(const fs::path& p)
{
    uint64_t n = 0;
    for (const auto& e : fs::recursive_directory_iterator(p))
        if (e.is_regular_file()) n += e.file_size();
    return n;
}

/// The floor: copying the bag's MCAP file.
double copySeconds(const fs::path& from, const fs::path& to)
{
    fs::remove(to);
    const auto t0 = std::chrono::steady_clock::now();
    fs::copy_file(from, to);
    return since(t0);
}

void report(const char* what, uint64_t bytes, double write_s, double read_s, double copy_s, uint64_t other,
            const char* other_name)
{
    const double mb = double(bytes) / 1e6;
    std::printf(
        "%-8s bag %8.1f MB: write %6.2f s (%7.1f MB/s), read %6.2f s (%7.1f MB/s), copy %6.2f s (%7.1f MB/s); "
        "%s %8.1f MB (bag/%s %.2f)\n",
        what, mb, write_s, mb / write_s, read_s, mb / read_s, copy_s, mb / copy_s, other_name, double(other) / 1e6,
        other_name, double(bytes) / double(other));
}

}  // namespace

int main(int argc, char** argv)
{
    const double os1_s = argc > 1 ? std::atof(argv[1]) : 60;
    const fs::path dir = fs::path(argc > 2 ? argv[2] : "/tmp") / "smokescan_bench_bag";
    fs::remove_all(dir);
    fs::create_directories(dir);
    // URG-04LX: 6 minutes at 3 Hz in bocas's smoke.
    {
        const Scene scene = loadScene("bocas");
        const SurfaceSet surfaces(scene);
        ScanConfig cfg;
        cfg.rate_hz = 3;
        cfg.from_s = 0;
        cfg.to_s = 360;
        cfg.keep_beams = false;
        const Scanner sc(scene, surfaces, cfg);
        std::vector<Scan> scans;
        for (double t : sc.times()) scans.push_back(sc.scanAt(t, scans.size()));
        auto t0 = std::chrono::steady_clock::now();
        {
            ScanBag bag((dir / "urg").string(), scene);
            for (const Scan& s : scans) bag.add(s, sc.spec(), sc.mount());
            bag.finish();
            bag.commit();
        }
        const double write_s = since(t0);
        t0 = std::chrono::steady_clock::now();
        const BagLaserScans back = readBagLaserScans((dir / "urg").string(), "");
        const double read_s = since(t0);
        writeLaserLog((dir / "urg.log").string(), {"bench"}, scans, sc.spec());
        const fs::path mcap = dir / "urg" / "urg_0.mcap";
        report("urg04lx", fs::file_size(mcap), write_s, read_s, copySeconds(mcap, dir / "copy"),
               fs::file_size(dir / "urg.log"), "log");
        std::printf("         %zu scans written and read back\n", back.scans.size());
    }
    // OS1-128: 10 simulated frames, repeated to os1_s seconds.
    {
        const Scene scene = loadScene("plume");
        const SurfaceSet surfaces(scene);
        LidarSpec spec = lidarSpec("os1-128");
        configureLidar(spec, 10, 1024, "bench", "bench");
        const LidarScanner scanner(scene, surfaces, defaultLidarMount(scene, spec.name), spec, ReturnMode::Dual, 1);
        std::vector<LidarFrame> frames;
        for (int k = 0; k < 10; ++k) frames.push_back(scanner.frame(20 + 0.1 * k, uint64_t(k)));
        const int n = int(os1_s * 10);
        const SensorMount mount = defaultLidarMount(scene, spec.name);
        auto t0 = std::chrono::steady_clock::now();
        {
            ScanBag bag((dir / "os1").string(), scene);
            for (int k = 0; k < n; ++k) {
                LidarFrame f = frames[size_t(k % 10)];
                f.start_s = 20 + 0.1 * k;
                bag.add(f, mount);
            }
            bag.finish();
            bag.commit();
        }
        const double write_s = since(t0);
        t0 = std::chrono::steady_clock::now();
        uint64_t points = 0;
        (void)readMcap((dir / "os1" / "os1_0.mcap").string(), [&](const McapChannel& ch, McapMessage&& m) {
            if (ch.topic == "/points") points += decodePointCloud2(m.data, "frame").width;
        });
        const double read_s = since(t0);
        fs::create_directories(dir / "pcd");
        for (int k = 0; k < 10; ++k) writePcd((dir / "pcd" / (std::to_string(k) + ".pcd")).string(), frames[size_t(k)]);
        const fs::path mcap = dir / "os1" / "os1_0.mcap";
        report("os1-128", fs::file_size(mcap), write_s, read_s, copySeconds(mcap, dir / "copy"),
               folderBytes(dir / "pcd") * uint64_t(n) / 10, "pcd");
        std::printf("         %d frames, %.1f M points written and read back\n", n, 1e-6 * double(points));
    }
    fs::remove_all(dir);
    return 0;
}
