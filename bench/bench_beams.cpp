// Beam throughput: smokescan's hierarchical optical-depth walk beside a naive yardstick in the
// same run. The yardstick walks every voxel along the beam's whole segment with an OpenVDB
// ValueAccessor (Amanatides–Woo, no hierarchy, no empty-space clipping), as a first
// implementation would. Counters: beams/s, and voxel segments/s = voxels the beam crosses (as the
// naive walk counts them) integrated per second.
#include <benchmark/benchmark.h>
#include <openvdb/openvdb.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <random>

#include "../src/media/vdb_grid.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/sensors/scanner.hpp"

using namespace smokescan;

namespace {

/// $SMOKESCAN_EXTERNAL_VDB/teapot_cloud.vdb, or "" when it is not there.
std::string externalTeapot()
{
    const char* dir = std::getenv("SMOKESCAN_EXTERNAL_VDB");
    const std::string p = dir && *dir ? std::string(dir) + "/teapot_cloud.vdb" : "";
    return !p.empty() && std::filesystem::is_regular_file(p) ? p : "";
}

struct Beam {
    Ray ray;
    double t0, t1;
};

/// Naive per-voxel DDA over [t0, t1]; returns ∫ρ ds and counts the voxels visited.
double naiveWalk(const DensityGrid& g, const Beam& b, long long& voxels)
{
    const auto& I = g.impl();
    const Eigen::Vector3d o = I.w2i_lin * b.ray.o + I.w2i_off + Eigen::Vector3d::Constant(0.5);
    const Eigen::Vector3d d = I.w2i_lin * b.ray.d;
    auto acc = I.grid->getConstAccessor();
    int c[3], step[3];
    double tn[3], dt[3];
    for (int a = 0; a < 3; ++a) {
        const double x = o[a] + d[a] * b.t0;
        c[a] = int(std::floor(x));
        step[a] = d[a] >= 0 ? 1 : -1;
        dt[a] = d[a] != 0 ? std::abs(1.0 / d[a]) : kInf;
        tn[a] = d[a] != 0 ? b.t0 + ((d[a] > 0 ? c[a] + 1 : c[a]) - x) / d[a] : kInf;
    }
    double t = b.t0, sum = 0;
    while (t < b.t1) {
        const int a = tn[0] <= tn[1] ? (tn[0] <= tn[2] ? 0 : 2) : (tn[1] <= tn[2] ? 1 : 2);
        const double te = std::min(tn[a], b.t1);
        sum += acc.getValue(openvdb::Coord(c[0], c[1], c[2])) * (te - t);
        ++voxels;
        t = te;
        c[a] += step[a];
        tn[a] += dt[a];
    }
    return sum;
}

struct Case {
    std::shared_ptr<DensityGrid> grid;
    std::vector<Beam> beams;
    long long voxels_per_pass = 0;
};

/// Random beams through the grid's bounds (chords plus a margin).
std::vector<Beam> randomBeams(const DensityGrid& g, int n)
{
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(-1, 1);
    const Aabb b = g.worldBounds();
    const Vec3 c = 0.5 * (b.lo + b.hi);
    const double r = 0.5 * (b.hi - b.lo).norm();
    std::vector<Beam> out;
    while (int(out.size()) < n) {
        const Vec3 d = Vec3(U(rng), U(rng), U(rng)).normalized();
        const Vec3 o = c - 1.2 * r * d + 0.3 * r * Vec3(U(rng), U(rng), U(rng));
        out.push_back({Ray{o, d}, 0.0, 2.4 * r});
    }
    return out;
}

/// The URG-04LX beams of the bocas room, each up to its surface, through the room's smoke grid.
std::vector<Beam> bocasBeams(const Scene& scene, const SurfaceSet& set)
{
    const Scanner sc(scene, set, ScanConfig{"urg04lx"});
    std::vector<Beam> out;
    for (int i = 0; i < sc.spec().n_beams; ++i) {
        const Ray r = sc.beamRay(i);
        const SurfaceHit h = set.closest(r, sc.spec().range_max_m);
        out.push_back({r, 0.0, h.hit ? h.t_m : sc.spec().range_max_m});
    }
    return out;
}

Case& getCase(const std::string& name)
{
    static std::map<std::string, Case> cases;
    auto it = cases.find(name);
    if (it != cases.end()) return it->second;
    ensureOpenVdb();
    Case c;
    if (name == "empty_room" || name == "smoke_area") {
        // The bocas room's smoke grid (5 cm voxels, interior as tiles) along the URG-04LX beams;
        // the empty room is the same grid with zero density (the naive walk cannot know that).
        static const Scene scene = loadScene("bocas");
        static const SurfaceSet set(scene);
        const auto& room = *std::get<std::shared_ptr<const DensityGrid>>(scene.volumes.at(0).source);
        c.grid = std::make_shared<DensityGrid>(room.scaled(name == "empty_room" ? 0.0 : 0.005));
        c.beams = bocasBeams(scene, set);
    } else if (name == "teapot_cloud") {
        c.grid = std::make_shared<DensityGrid>(DensityGrid::loadVdb(externalTeapot()));
        c.beams = randomBeams(*c.grid, 2000);
    } else {  // dense_N: random values in every voxel of an N³ block (256³: 64 MB, 64³: 1 MB, in cache)
        const int N = std::stoi(name.substr(6));
        auto g = openvdb::FloatGrid::create(0.0f);
        g->setTransform(openvdb::math::Transform::createLinearTransform(0.01));
        auto acc = g->getAccessor();
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> U(0.f, 1.f);
        for (int i = 0; i < N; ++i)
            for (int j = 0; j < N; ++j)
                for (int k = 0; k < N; ++k) acc.setValueOn(openvdb::Coord(i, j, k), U(rng));
        c.grid = std::make_shared<DensityGrid>(wrapFloatGrid(g));
        c.beams = randomBeams(*c.grid, 1000);
    }
    for (const Beam& b : c.beams) naiveWalk(*c.grid, b, c.voxels_per_pass);
    return cases.emplace(name, std::move(c)).first->second;
}

void report(benchmark::State& st, const Case& c)
{
    st.counters["beams/s"] = benchmark::Counter(double(c.beams.size()), benchmark::Counter::kIsIterationInvariantRate);
    st.counters["voxel_segments/s"] =
        benchmark::Counter(double(c.voxels_per_pass), benchmark::Counter::kIsIterationInvariantRate);
}

/// One pass of each walk over the case's beams.
void hierarchicalPass(const Case& c)
{
    double s = 0;
    for (const Beam& b : c.beams) s += c.grid->integrate(b.ray, b.t0, b.t1);
    benchmark::DoNotOptimize(s);
}

void naivePass(const Case& c)
{
    double s = 0;
    long long v = 0;
    for (const Beam& b : c.beams) s += naiveWalk(*c.grid, b, v);
    benchmark::DoNotOptimize(s);
}

void BM_Hierarchical(benchmark::State& st, const std::string& name)
{
    const Case& c = getCase(name);
    for (auto _ : st) hierarchicalPass(c);
    report(st, c);
}

void BM_Naive(benchmark::State& st, const std::string& name)
{
    const Case& c = getCase(name);
    for (auto _ : st) naivePass(c);
    report(st, c);
}

/// Both walks over the same beams in alternating order within each iteration, so that the
/// machine's slow spells (it is shared) fall on both: speed-up = naive time / smokescan time.
void BM_SpeedUp(benchmark::State& st, const std::string& name)
{
    using Clock = std::chrono::steady_clock;
    const Case& c = getCase(name);
    double t_hier = 0, t_naive = 0;
    auto timed = [&](void (*pass)(const Case&), double& total) {
        const auto a = Clock::now();
        pass(c);
        total += std::chrono::duration<double>(Clock::now() - a).count();
    };
    bool hier_first = true;
    for (auto _ : st) {
        if (hier_first) timed(hierarchicalPass, t_hier);
        timed(naivePass, t_naive);
        if (!hier_first) timed(hierarchicalPass, t_hier);
        hier_first = !hier_first;
    }
    st.counters["speed-up"] = t_naive / t_hier;
}

/// A full scan of the bocas room in smoke (t = 150 s) on one core: URG-04LX with the paper or the
/// physical model, and the LMS200 (physical) of the plume scene at t = 60 s.
void BM_FullScanOneCore(benchmark::State& st, const std::string& model, const std::string& scene_name)
{
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    const Scene scene = loadScene(scene_name);
    const SurfaceSet set(scene);
    ScanConfig cfg;
    cfg.model = parseSensorModel(model);
    cfg.keep_beams = false;
    const Scanner sc(scene, set, cfg);
    const double t = scene_name == "bocas" ? 150.0 : 60.0;
    uint64_t k = 0;
    for (auto _ : st) benchmark::DoNotOptimize(sc.scanAt(t, k++));
    st.counters["time/beam"] = benchmark::Counter(
        double(sc.spec().n_beams), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
    st.counters["beams/s"] =
        benchmark::Counter(double(sc.spec().n_beams), benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

int main(int argc, char** argv)
{
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    // The teapot cloud is a third-party file (no licence to ship it): its case runs only when
    // SMOKESCAN_EXTERNAL_VDB names the folder holding teapot_cloud.vdb.
    const bool teapot = !externalTeapot().empty();
    if (!teapot)
        std::fprintf(
            stderr,
            "skipping optical_depth/teapot_cloud: set SMOKESCAN_EXTERNAL_VDB to the folder holding teapot_cloud.vdb\n");
    for (const std::string n : {"empty_room", "smoke_area", "teapot_cloud", "dense_256", "dense_64"}) {
        if (n == "teapot_cloud" && !teapot) continue;
        benchmark::RegisterBenchmark(("optical_depth/" + n + "/hierarchical").c_str(), BM_Hierarchical, n)
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("optical_depth/" + n + "/naive_dda").c_str(), BM_Naive, n)
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("optical_depth/" + n + "/speed-up").c_str(), BM_SpeedUp, n)
            ->Unit(benchmark::kMillisecond);
    }
    benchmark::RegisterBenchmark("scan/urg04lx_bocas_smoke_1core/paper", BM_FullScanOneCore, "paper", "bocas")
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark("scan/urg04lx_bocas_smoke_1core/physical", BM_FullScanOneCore, "physical", "bocas")
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark("scan/lms200_plume_1core/paper", BM_FullScanOneCore, "paper", "plume")
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark("scan/lms200_plume_1core/physical", BM_FullScanOneCore, "physical", "plume")
        ->Unit(benchmark::kMicrosecond);
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
}
