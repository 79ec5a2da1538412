// Diagnosis throughput (issue target: a 6-minute 3 Hz URG-04LX run, 1081 scans × 682 beams,
// diagnosed in under 60 s on 2 cores). In one run: the BOCAS run simulated (the yardstick: what
// producing the same run costs), then replayed and diagnosed, clean and with the gold paper's
// range bias planted (one finding: a second greedy round and the held-out figures).
//   ./build/smokescan_bench_diagnose [seconds of run] [scan rate Hz]
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "../tests/plant.hpp"
#include "smokescan/diagnose/diagnosis.hpp"

using namespace smokescan;
using namespace smokescan::test;

namespace {

double seconds(std::chrono::steady_clock::time_point t0)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void diagnoseTimed(const char* name, const TrueRun& r)
{
    auto t0 = std::chrono::steady_clock::now();
    const FitInputs in = inputsOf(r);
    const Replay replay = replayRun(in, in.mount.config, ReplayConfig{});
    const double t_replay = seconds(t0);
    t0 = std::chrono::steady_clock::now();
    const DiagnosisResult d = diagnose(replay);
    const double t_diag = seconds(t0);
    std::printf("%-8s replay %6.2f s, diagnose %6.2f s, total %6.2f s (%lld observations, %.2f M/s); verdict: %s\n",
                name, t_replay, t_diag, t_replay + t_diag, d.observations,
                1e-6 * double(d.observations) / (t_replay + t_diag), d.verdict.c_str());
}

}  // namespace

int main(int argc, char** argv)
{
    const double run_s = argc > 1 ? std::atof(argv[1]) : 360.0, rate = argc > 2 ? std::atof(argv[2]) : 3.0;
    if (!(run_s > 0 && run_s <= 3600 && rate > 0 && rate <= 40)) {
        std::fprintf(stderr, "usage: smokescan_bench_diagnose [seconds 0-3600] [rate Hz 0-40]\n");
        return 2;
    }
    auto t0 = std::chrono::steady_clock::now();
    TrueRun r = simulateBocas(7, run_s, rate);
    const double t_sim = seconds(t0);
    std::printf("run: %zu scans x %zu beams; simulating it (scan + camera, the yardstick) %.2f s\n", r.scans.size(),
                r.scans.front().value.size(), t_sim);
    diagnoseTimed("clean", r);
    plant(r, [](BeamView& v) {
        if (v.surface == "target_gold" && !v.truth.error) v.value = std::llround(double(v.value) * (1 + 14 * v.column));
    });
    diagnoseTimed("planted", r);
    return 0;
}
