// The diagnosis in rooms nobody here drew (random_room.hpp): what holds on BOCAS must hold there.
// Clean runs name nothing beyond the stated false-alarm rate; each cause planted above its
// stated detectability (its floor, docs/diagnosis.md §4) is found with the right target, and its
// magnitude within its reported errors. Effects are planted through their own mechanisms, not the
// candidates' forms, on the true column along each beam (plant.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <memory>

#include "normal_cdf.hpp"
#include "plant.hpp"
#include "random_room.hpp"
#include "scratch.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/diagnose/diagnosis.hpp"

using namespace smokescan;
using namespace smokescan::test;

namespace {

/// A drawn room as a world for plant.hpp.
std::unique_ptr<World> worldOf(const DrawnRoom& room, uint64_t seed)
{
    return std::make_unique<World>(parseScene(room.text, "drawn room " + std::to_string(seed), "."));
}

struct RoomRun {
    DrawnRoom room;
    std::unique_ptr<World> world;
    TrueRun run;
};

RoomRun simulateRoom(uint64_t seed, const std::string& sensor_file = "")
{
    RoomRun r{drawRoom(seed), nullptr, {}};
    r.world = worldOf(r.room, seed);
    r.run = simulateRun(*r.world, seed, r.room.to_s, r.room.rate_hz, 0.01, 0, sensor_file);
    return r;
}

/// @brief The drawn room of `seed` simulated with `target`'s NIR reflectance (what the physical
/// model sees; the camera sees its colour) scaled by `factor`, while the room the diagnosis is
/// given still says the drawn value: a target darker or brighter in the infrared than its scene
/// file states, a mechanism no candidate assumes (they scale the smoke, not the echo).
RoomRun simulateRoomWithTargetNir(uint64_t seed, const std::string& sensor_file, const std::string& target,
                                  double factor)
{
    RoomRun r{drawRoom(seed), nullptr, {}};
    r.world = worldOf(r.room, seed);
    Scene seen = r.world->scene;
    const int s = seen.findSurface(target);
    if (s < 0) throw Error("test", "no surface " + target);
    Material m = seen.materials[size_t(seen.surfaces[size_t(s)].material)];
    m.name += "_as_measured";
    m.nir_785 *= factor;
    m.nir_905 *= factor;
    seen.materials.push_back(m);
    seen.surfaces[size_t(s)].material = int(seen.materials.size()) - 1;
    const World truth(std::move(seen));
    r.run = simulateRun(truth, seed, r.room.to_s, r.room.rate_hz, 0.01, 0, sensor_file);
    r.run.world = r.world.get();
    return r;
}

DiagnosisResult diagnoseRoom(const TrueRun& run, SensorModel model = SensorModel::Paper)
{
    const FitInputs in = inputsOf(run);
    SensorConfig c = in.mount.config;
    c.model = model;
    return diagnose(replayRun(in, c, ReplayConfig{}));
}

std::string describeRun(const RoomRun& r, const DiagnosisResult& d)
{
    return r.room.describe() + ": " + findingsText(d);
}

/// One effect planted into a drawn room's run: the cause, its target, the planted value of the
/// finding's first parameter and of its effect (the cause's floor units).
struct Planted {
    std::string cause, target;
    double value = 0, effect = 0;
};

/// The mean of L/σ₀ over the first scan's beams on `surface` ("" every surface), and of 1/σ₀
/// [1/m]: the scale a range bias or noise growth is measured in (docs/diagnosis.md §4).
std::pair<double, double> noiseScale(const RoomRun& rr, const std::string& surface)
{
    const Scan& first = rr.run.scans.front();
    double l_sd = 0, inv_sd = 0;
    int n = 0;
    for (const BeamResult& b : first.beams) {
        if (b.hit.surface < 0) continue;
        if (!surface.empty() && rr.world->scene.surfaces[size_t(b.hit.surface)].name != surface) continue;
        const double L = b.hit.t_m, sd = rr.run.spec.rangeSigma(L);
        if (L > rr.run.spec.range_max_m) continue;
        l_sd += L / sd;
        inv_sd += 1 / sd;
        ++n;
    }
    return {n ? l_sd / n : 0.0, n ? inv_sd / n : 0.0};
}

/// @brief Plants cause `which` (0–7) at a random magnitude well above its floor, through its own
/// mechanism on the true column (the paper model's threshold P on it), not the candidate's form.
Planted plantInRoom(int which, RoomRun& rr, uint64_t seed)
{
    TrueRun& r = rr.run;
    KeyedRng rng(seed, 0x9147u, uint64_t(which));
    const double P = 0.007;
    const std::string target =
        rr.room.targets[size_t(rng.uniform() * double(rr.room.targets.size())) % rr.room.targets.size()];
    auto smokeError = [](const BeamView& v) {
        return v.truth.error && std::string(v.truth.cause) == "penetration_power";
    };
    // Errors from a threshold at column `at` (or none): turned on or off against the truth.
    auto threshold = [&](BeamView& v, bool err) {
        if (err && !v.truth.error) v.value = 0;
        if (!err && smokeError(v)) v.value = surfaceReading(r, v, rng);
    };
    switch (which) {
    case 0: {  // the target reads long as smoke thickens: 6–14 % at the column P
        const double beta = (0.06 + 0.08 * rng.uniform()) / P;
        plant(r, [&](BeamView& v) {
            if (v.surface == target && !v.truth.error) v.value = std::llround(double(v.value) * (1 + beta * v.column));
        });
        return {"surface_range_bias", target, beta, beta * P * noiseScale(rr, target).first};
    }
    case 1: {  // the target fails at a 35–70 % higher or 25–40 % lower column
        const double f = rng.uniform() < 0.5 ? 1.35 + 0.35 * rng.uniform() : 0.6 + 0.15 * rng.uniform();
        plant(r, [&](BeamView& v) {
            if (v.surface == target && v.truth.hit.hit && !(v.truth.error && !smokeError(v)))
                threshold(v, v.column > P * f);
        });
        return {"surface_threshold", target, std::log(f), std::abs(std::log(f))};
    }
    case 2: {  // a gradual onset: each beam's threshold drawn anew, width 0.15–0.3 in ln(column)
        const double w = 0.15 + 0.15 * rng.uniform();
        plant(r, [&](BeamView& v) {
            if (!v.truth.hit.hit || !(v.column > 0) || (v.truth.error && !smokeError(v))) return;
            threshold(v, rng.uniform() < normalCdf((std::log(v.column) - std::log(P)) / w));
        });
        return {"threshold_width", "", w, w};
    }
    case 3: {  // range noise growing with the column: 3–6 m per density·m
        const double g = 3 + 3 * rng.uniform();
        plant(r, [&](BeamView& v) {
            if (!v.truth.error) v.value += std::llround(g * v.column * rng.normal() / r.spec.unit_m);
        });
        return {"range_noise_growth", "", g, g * P * noiseScale(rr, "").second};
    }
    case 4: {  // 25–45 % of the smoke failures return a short range instead
        const double q = 0.25 + 0.2 * rng.uniform();
        plant(r, [&](BeamView& v) {
            if (smokeError(v) && v.truth.hit.hit && rng.uniform() < q)
                v.value = std::llround((0.1 + (v.truth.hit.t_m - 0.1) * rng.uniform()) / r.spec.unit_m);
        });
        return {"smoke_obstacle_return", "", q, q};
    }
    case 5: {  // a dirty window: a 12–25° sector of beams that see a wall (not the target) fails 30–60 %
        const double d = 0.3 + 0.3 * rng.uniform(), width = 12 + 13 * rng.uniform();
        // Where it may start: a beam of the first scan that hits something other than the target,
        // with at least five such beams in the sector (a hall's far walls lie beyond the URG's range).
        const Scan& first = r.scans.front();
        std::vector<double> wall_deg;
        for (size_t i = 0; i < first.beams.size(); ++i) {
            const int s = first.beams[i].hit.surface;
            if (s >= 0 && rr.world->scene.surfaces[size_t(s)].name.rfind("target_", 0) != 0)
                wall_deg.push_back(first.angle_rad[i] * 180 / M_PI);
        }
        std::vector<double> starts;
        for (double a : wall_deg) {
            const auto in =
                std::count_if(wall_deg.begin(), wall_deg.end(), [&](double x) { return x >= a && x <= a + width; });
            if (in >= 5 && std::abs(a + 0.5 * width) > 20) starts.push_back(a);
        }
        const double from =
            starts.empty() ? 30.0 : starts[size_t(rng.uniform() * double(starts.size())) % starts.size()];
        plant(r, [&](BeamView& v) {
            const double deg = v.angle_rad * 180 / M_PI;
            if (deg >= from && deg <= from + width && v.truth.hit.hit && rng.uniform() < d) v.value = 0;
        });
        return {"sector_dropout", "", d, d};
    }
    case 6: {  // the onset while smoke falls lies 0.5–0.8 higher in ln(column) than while it rises
        const double h = 0.5 + 0.3 * rng.uniform();
        plant(r, [&](BeamView& v) {
            if (!v.truth.hit.hit || (v.truth.error && !smokeError(v))) return;
            threshold(v, v.column > P * std::exp(v.column > v.previous_column ? -0.5 * h : 0.5 * h));
        });
        return {"hysteresis", "", h, h};
    }
    default: {  // the camera's clock 3–8 s ahead or behind: the saturation series shifted
        const double dt = (rng.uniform() < 0.5 ? -1 : 1) * (3 + 5 * rng.uniform());
        for (double& t : r.sat.time_s) t += dt;
        return {"clock_offset", "", dt, std::abs(dt)};
    }
    }
}

/// The causes the rooms test plants (plantInRoom's 0–6). A clock offset (7) is not yet found in
/// every drawn room it is detectable in: in a corridor with puffs scanned at 10 Hz a planted −3 s
/// fits −2.3 s on one fold and −2.8 s on the other and the held-out test fails (p 0.2). Open in
/// issue 32; `SMOKESCAN_EXPLORE_PLANT=7` in the Explore test shows it.
constexpr int kPlantable = 7;

}  // namespace

namespace {

/// The normal quantile of a one-sided level (bisection on the tail).
double zOf(double level)
{
    double lo = 0, hi = 10;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (1 - normalCdf(mid) > level ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

/// The planted cause's detectability on this run as docs/diagnosis.md §4 states it, from what the
/// run's first round reports for the cause (and target): its floor, or (z + 1.64) of the effect's
/// standard error, z the normal quantile of its level; infinite when its gain is spread over too
/// few blocks for the sign-flip test to reach the level (2^−blocks ≥ level) or it was not tried.
double detectability(const DiagnosisResult& d, const Planted& p)
{
    const Tried* mine = nullptr;
    for (const Tried& t : d.tried)
        if (t.round == 1 && t.cause == p.cause && (p.target.empty() || t.target == p.target)) mine = &t;
    if (!mine || std::exp2(-mine->blocks) >= mine->level) return INFINITY;
    return std::max(mine->floor, (zOf(mine->level) + 1.64) * mine->effect_se);
}

}  // namespace

TEST(DiagnoseRooms, CleanRunsNameNothingBeyondTheStatedRate)
{
    if (sanitized()) GTEST_SKIP() << "drawn rooms over seeds: the Release build";
    // Ten drawn rooms, the paper model: a cause named in at most two (5 % a round; two or fewer
    // of ten has probability 0.99 at that rate).
    int named = 0;
    std::string seen;
    for (uint64_t seed = 5000; seed < 5010; ++seed) {
        RoomRun r = simulateRoom(seed);
        const DiagnosisResult d = diagnoseRoom(r.run);
        if (!d.findings.empty()) ++named, seen += describeRun(r, d) + "\n";
        // A drawn room's smoke keeps its shape (one volume whose density follows a time line).
        EXPECT_LT(d.shape_error_ln, 0.05) << describeRun(r, d);
    }
    EXPECT_LE(named, 2) << seen;
}

TEST(DiagnoseRooms, EachCauseAboveItsDetectabilityIsFoundWithItsTarget)
{
    if (sanitized()) GTEST_SKIP() << "drawn rooms over seeds: the Release build";
    // Each cause planted into two drawn rooms of its own (14 rooms): where the planted effect is
    // above the detectability the run itself states, it is found with its target. Most plants
    // must be detectable, or the test would test nothing. The values' pulls are printed, not
    // asserted: in drawn rooms they are not yet of unit spread (issue 32; docs/diagnosis.md).
    int detectable = 0, runs = 0, with_extra = 0;
    std::vector<double> pulls;
    std::string extras;
    for (int which = 0; which < kPlantable; ++which) {
        int detectable_here = 0;
        for (int i = 0; i < 2; ++i) {
            const uint64_t seed = 6000 + 10 * uint64_t(which) + uint64_t(i);
            RoomRun r = simulateRoom(seed);
            const Planted p = plantInRoom(which, r, seed);
            const DiagnosisResult d = diagnoseRoom(r.run);
            ++runs;
            const double needed = detectability(d, p);
            const std::string what = p.cause + " " + p.target + " planted " + std::to_string(p.value) + " (effect " +
                std::to_string(p.effect) + ", detectable from " + std::to_string(needed) + ") in " + describeRun(r, d);
            if (!(p.effect >= needed)) {
                std::printf("below its detectability: %s\n", what.c_str());
                continue;
            }
            ++detectable;
            ++detectable_here;
            const Finding* f = nullptr;
            for (const Finding& x : d.findings)
                if (x.cause == p.cause && (p.target.empty() || x.target == p.target)) f = &x;
            ASSERT_NE(f, nullptr) << what;
            if (d.findings.size() > 1) ++with_extra, extras += what + "\n";
            const Estimate e = f->parameters.front().second;
            pulls.push_back((e.value - p.value) / e.se);
            std::printf("found: %s, pull %.2f\n", what.c_str(), pulls.back());
        }
        // Each cause detectable in at least one of its rooms: a cause never tried (a sector search
        // that finds nothing) or never stating its detectability would otherwise pass unseen.
        EXPECT_GE(detectable_here, 1) << "cause " << which << " was detectable in none of its rooms";
    }
    EXPECT_GE(detectable, runs * 3 / 4) << "most plants must be above the detectability the runs state";
    // Another cause named beside the planted one in at most a quarter of the runs, as on BOCAS.
    EXPECT_LE(with_extra, runs / 4) << extras;
    double m = 0, m2 = 0;
    for (double x : pulls) m += x / double(pulls.size()), m2 += x * x / double(pulls.size());
    std::printf("pulls over %zu found plants: mean %.2f, sd %.2f\n", pulls.size(), m, std::sqrt(m2 - m * m));
}

namespace {

/// A sensor file that turns the drawn rooms' URG-04LX to the physical model (its AMCW receiver).
std::string physicalUrgFile()
{
    const std::string path = (smokescan::test::scratch("rooms_physical") / "urg_physical.toml").string();
    std::ofstream(path) << "type = \"urg04lx\"\nmodel = \"physical\"\n";
    return path;
}

}  // namespace

TEST(DiagnoseRooms, ThePhysicalModelNamesNothingOnCleanRunsAndFindsWhatActsOnAnyReading)
{
    if (sanitized()) GTEST_SKIP() << "drawn rooms over seeds: the Release build";
    // Runs simulated with the physical model and diagnosed with it. Five clean rooms: a cause
    // named in at most one (5 % a round; two or more of five has probability 0.023 at that rate).
    const std::string sensor = physicalUrgFile();
    int named = 0;
    std::string seen;
    for (uint64_t seed = 5100; seed < 5105; ++seed) {
        RoomRun r = simulateRoom(seed, sensor);
        const DiagnosisResult d = diagnoseRoom(r.run, SensorModel::Physical);
        if (!d.findings.empty()) ++named, seen += describeRun(r, d) + "\n";
    }
    EXPECT_LE(named, 1) << seen;
    // The plants that act on readings whatever made them (the threshold plants act on the paper
    // model's smoke errors): a target reading long, range noise growing with the column, a dirty
    // window; each in a room where the run states it detectable, found alone with its target.
    std::vector<double> pulls;
    for (const auto& [which, seed] : {std::pair{0, 6105}, std::pair{3, 6130}, std::pair{5, 6150}}) {
        RoomRun r = simulateRoom(uint64_t(seed), sensor);
        const Planted p = plantInRoom(which, r, uint64_t(seed));
        const DiagnosisResult d = diagnoseRoom(r.run, SensorModel::Physical);
        const std::string what =
            p.cause + " " + p.target + " planted " + std::to_string(p.value) + " in " + describeRun(r, d);
        ASSERT_GE(p.effect, detectability(d, p)) << what;
        ASSERT_EQ(d.findings.size(), 1u) << what;
        const Finding& f = d.findings.front();
        EXPECT_EQ(f.cause, p.cause) << what;
        if (!p.target.empty()) EXPECT_EQ(f.target, p.target) << what;
        const Estimate e = f.parameters.front().second;
        pulls.push_back((e.value - p.value) / e.se);
        std::printf("physical model, found: %s, pull %.2f\n", what.c_str(), pulls.back());
    }
}

TEST(DiagnoseRooms, ThePhysicalModelFindsATargetDarkerInTheInfraredAsItsThresholdWhereTheRunCanTell)
{
    if (sanitized()) GTEST_SKIP() << "drawn rooms over seeds: the Release build";
    // A threshold planted through the physics: the run simulated with the target's NIR
    // reflectance 0.45 or 0.6 of what the room's scene says (a target measured in visible light), and
    // diagnosed against that scene. The darker echo drowns in less smoke, so the target errs
    // earlier: no candidate assumes this (a threshold scales the smoke, not the echo). Where the
    // held-out test can reach its level on the blocks the run has (§4: 2^−blocks below it), the
    // target's surface_threshold is named, alone, with a lower threshold (θ < 0) and a finite
    // error; where it is missed, the run must say it could not tell (its candidate fitted, with
    // an error, on blocks too few for the level). With the tables linear in u (before 9f7e6f9) the
    // likelihood's kinks at their grid left the lab (6105) with verdict none on 10,000 nats of
    // gain and rooms 6204 and 6206 with findings ± nan.
    const std::string sensor = physicalUrgFile();
    int found = 0, rooms = 0;
    for (const auto& [seed, factor] :
         {std::pair{6105u, 0.45}, std::pair{6200u, 0.6}, std::pair{6201u, 0.6}, std::pair{6203u, 0.6},
          std::pair{6204u, 0.6}, std::pair{6205u, 0.6}, std::pair{6206u, 0.6}, std::pair{6207u, 0.6}}) {
        const std::string target = drawRoom(seed).targets.front();
        RoomRun r = simulateRoomWithTargetNir(seed, sensor, target, factor);
        const DiagnosisResult d = diagnoseRoom(r.run, SensorModel::Physical);
        ++rooms;
        const std::string what = target + " at " + std::to_string(factor) + " of its NIR in " + describeRun(r, d);
        const Finding* f = nullptr;
        for (const Finding& x : d.findings)
            if (x.cause == "surface_threshold" && x.target == target) f = &x;
        if (!f) {
            const Tried* t = nullptr;
            for (const Tried& x : d.tried)
                if (x.round == 1 && x.cause == "surface_threshold" && x.target == target) t = &x;
            ASSERT_NE(t, nullptr) << "never tried: " << what;
            EXPECT_TRUE(t->blocks > 0 && std::isfinite(t->effect_se)) << "not fitted: " << what;
            EXPECT_GE(std::exp2(-t->blocks), t->level) << "missed where the run could tell: " << what;
            std::printf("not found, the run could not tell (%.1f blocks, level %.2g): %s\n", t->blocks, t->level,
                        what.c_str());
            continue;
        }
        ++found;
        EXPECT_EQ(d.findings.size(), 1u) << what;
        const Estimate e = f->parameters.front().second;
        EXPECT_LT(e.value, 0) << what;
        EXPECT_TRUE(std::isfinite(e.se) && e.se > 0 && e.se < std::abs(e.value)) << what;
        std::printf("found: %s\n", what.c_str());
    }
    EXPECT_GT(found, rooms / 2) << "most rooms must tell, or the test would test nothing";
}

TEST(DiagnoseRooms, Explore)
{
    // SMOKESCAN_EXPLORE=N rooms from seed 5000; SMOKESCAN_EXPLORE_PLANT=k plants cause k (−1: clean);
    // SMOKESCAN_EXPLORE_MODEL=physical diagnoses with the physical model, and simulates with it too;
    // SMOKESCAN_EXPLORE_NIR=f simulates the first target's NIR reflectance at f of the scene's.
    if (!std::getenv("SMOKESCAN_EXPLORE")) GTEST_SKIP() << "set SMOKESCAN_EXPLORE=N";
    const int n = std::atoi(std::getenv("SMOKESCAN_EXPLORE"));
    const int which = std::getenv("SMOKESCAN_EXPLORE_PLANT") ? std::atoi(std::getenv("SMOKESCAN_EXPLORE_PLANT")) : -1;
    const uint64_t first = std::getenv("SMOKESCAN_EXPLORE_FROM")
        ? std::strtoull(std::getenv("SMOKESCAN_EXPLORE_FROM"), nullptr, 10)
        : 5000;
    for (int s = 0; s < n; ++s) {
        const uint64_t seed = first + uint64_t(s);
        const auto t0 = std::chrono::steady_clock::now();
        const char* model = std::getenv("SMOKESCAN_EXPLORE_MODEL");  // paper (default) or physical
        const bool physical = model && std::string(model) == "physical";
        std::string sensor_file;
        if (physical) {
            sensor_file = (scratch("explore_physical") / "urg_physical.toml").string();
            std::ofstream(sensor_file) << "type = \"urg04lx\"\nmodel = \"physical\"\n";
        }
        const char* nir = std::getenv("SMOKESCAN_EXPLORE_NIR");
        RoomRun r = nir ? simulateRoomWithTargetNir(seed, sensor_file, drawRoom(seed).targets.front(), std::atof(nir))
                        : simulateRoom(seed, sensor_file);
        Planted p;
        if (which >= 0) p = plantInRoom(which, r, seed);
        const auto t1 = std::chrono::steady_clock::now();
        const DiagnosisResult d = diagnoseRoom(r.run, physical ? SensorModel::Physical : SensorModel::Paper);
        const auto t2 = std::chrono::steady_clock::now();
        std::printf(
            "%llu %s: %zu scans, sim %.1f s, diagnose %.1f s; planted %s %s %.4g (effect %.3g, detectable "
            "from %.3g)\n%s\n",
            (unsigned long long)seed, r.room.describe().c_str(), r.run.scans.size(),
            std::chrono::duration<double>(t1 - t0).count(), std::chrono::duration<double>(t2 - t1).count(),
            p.cause.c_str(), p.target.c_str(), p.value, p.effect, which >= 0 ? detectability(d, p) : 0.0,
            describeRun(r, d).c_str());
        for (const auto& t : d.tried)
            if (t.round == 1)
                std::printf("   tried %s %s gain %.1f p %.3g level %.2g blocks %.1f effect %.3g±%.2g floor %.3g\n",
                            t.cause.c_str(), t.target.c_str(), t.loglik_gain, t.p_value, t.level, t.blocks, t.effect,
                            t.effect_se, t.floor);
    }
}

namespace {

/// A lab whose smoke changes shape: a cloud on the URG's line to the target (the camera's view)
/// that comes and goes, then a second cloud off to the left of it (out of the camera's view) that
/// comes and goes later. The first cloud alone is the densest state the camera sees; its density
/// is `line_scale` times the scene's nominal one.
std::string shiftingSmokeLab(double line_scale)
{
    SceneText s;
    s.raw(
        "[scene]\nname = \"shifting\"\nt_start_s = 0\nt_end_s = 200\n"
        "[[materials]]\nname = \"white\"\nalbedo = [0.85, 0.85, 0.85]\nnir_905 = 0.88\n"
        "[[materials]]\nname = \"grey\"\nalbedo = [0.4, 0.4, 0.4]\nnir_905 = 0.45\n"
        "[[materials]]\nname = \"paper\"\nalbedo = [0.8, 0.1, 0.1]\nnir_905 = 0.8\n");
    const double x0 = -1, x1 = 4.5, y0 = -2.5, y1 = 2.5, h = 3;
    s.quad("floor", "grey", {x0, y0, 0}, {x1 - x0, 0, 0}, {0, y1 - y0, 0});
    s.quad("ceiling", "white", {x0, y0, h}, {x1 - x0, 0, 0}, {0, y1 - y0, 0});
    s.quad("wall_x0", "grey", {x0, y0, 0}, {0, y1 - y0, 0}, {0, 0, h});
    s.quad("wall_x1", "white", {x1, y0, 0}, {0, y1 - y0, 0}, {0, 0, h});
    s.quad("wall_y0", "grey", {x0, y0, 0}, {x1 - x0, 0, 0}, {0, 0, h});
    s.quad("wall_y1", "white", {x0, y1, 0}, {x1 - x0, 0, 0}, {0, 0, h});
    s.quad("target_a", "paper", {2.0, 0.2, 0.2}, {0, -0.4, 0}, {0, 0, 0.8});
    s.raw(
        "[[sensors]]\nname = \"hokuyo\"\ntype = \"urg04lx\"\nposition = [0.0, 0.0, 0.5]\n"
        "rpy_deg = [0.0, 0.0, 0.0]\nmodel = \"paper\"\npenetration_power = 0.007\n");
    s.camera({-0.3, 0, 0.62}, {2.0, 0, 0.6}, 320, 240, 40);
    s.ambient(1.0);
    auto cloud = [&](const std::string& name, std::array<double, 3> lo, std::array<double, 3> hi, double peak,
                     double t0) {
        s.raw("[[smoke]]\nname = \"" + name + "\"\ntype = \"box\"\nrole = \"regional\"\nmin = " + tomlVec(lo) +
              "\nmax = " + tomlVec(hi) + "\ndensity = " + tomlNumber(peak) + "\nvoxel = 0.05\nedge_m = 0.3\n" +
              "medium = \"theatrical_fog\"\ntimeline = { kind = \"keyframes\", keys = [[0, 0], [" + tomlNumber(t0) +
              ", 0], [" + tomlNumber(t0 + 30) + ", 1], [" + tomlNumber(t0 + 50) + ", 1], [" + tomlNumber(t0 + 80) +
              ", 0]] }\n");
    };
    cloud("on_the_line", {-0.6, -0.7, 0.025}, {2.4, 0.7, 2.975}, 0.0045 * line_scale, 10);
    cloud("to_the_left", {0.2, 0.9, 0.025}, {3.5, 2.475, 2.975}, 0.006, 100);
    return s.str();
}

}  // namespace

TEST(DiagnoseRooms, SmokeThatChangesShapeIsReportedAndReplayedFromTheTimeline)
{
    if (sanitized()) GTEST_SKIP() << "a 190 s run diagnosed twice: the Release build";
    // The replay's reference shape (the camera's densest state, scaled) puts no smoke on the
    // left while the second cloud is there: the URG's errors on the left wall go unexplained.
    // The report must say how far the reference shape misstates the scene's own columns, and
    // the timeline shape (the scene's state at each scan) must replay the run. The run's first
    // cloud is 25 % denser than the scene the diagnosis is given says: the camera's density over
    // the scene's must correct it, or the target's columns read 20 % low. A range bias planted on
    // the target is then found alone, its value within its errors.
    World w(parseScene(shiftingSmokeLab(1.25), "shifting smoke lab", "."));
    TrueRun run = simulateRun(w, 4242, 190, 4);
    const double beta = 0.12 / 0.007;  // 12 % long at the column P
    plant(run, [&](BeamView& v) {
        if (v.surface == "target_a" && !v.truth.error) v.value = std::llround(double(v.value) * (1 + beta * v.column));
    });
    FitInputs in = inputsOf(run);
    in.scene = std::make_unique<Scene>(parseScene(shiftingSmokeLab(1.0), "the lab as the user drew it", "."));
    in.surfaces = std::make_unique<SurfaceSet>(*in.scene);
    ReplayConfig rc;
    const Replay ref = replayRun(in, in.mount.config, rc);
    rc.shape = SmokeShape::Timeline;
    const Replay tl = replayRun(in, in.mount.config, rc);
    // The columns each shape replays against the run's own, where the smoke matters (P/5 up).
    auto lnError = [&](const Replay& rp) {
        double ss = 0;
        long n = 0;
        for (size_t k = 0, j = 0; k < rp.scans.size(); ++k) {
            while (run.scans[j].time_s < rp.scans[k].time_s - 1e-9) ++j;
            for (size_t b = 0; b < rp.beams.size(); ++b) {
                const double truth = run.scans[j].beams[b].smoke.column_regional;
                if (rp.beams[b].surface < 0 || truth < 0.007 / 5) continue;
                ss += std::pow(std::log((rp.columnAt(k, b) + 0.00035) / (truth + 0.00035)), 2);
                ++n;
            }
        }
        return std::sqrt(ss / double(n));
    };
    const double ref_error = lnError(ref), tl_error = lnError(tl);
    const DiagnosisResult dr = diagnose(ref), dt = diagnose(tl);
    std::printf("reference shape: columns off by %.2f in ln (it states %.2f): %s\ntimeline: off by %.2f: %s\n",
                ref_error, dr.shape_error_ln, findingsText(dr).c_str(), tl_error, findingsText(dt).c_str());
    EXPECT_GE(dr.shape_error_ln, kShapeWarningLn);
    EXPECT_NEAR(dr.shape_error_ln, ref_error, 0.2 * ref_error) << "the stated shape error is the one the run has";
    EXPECT_GE(ref_error, 0.5);
    // The camera sees the first cloud and not the second: the timeline scales the one and takes
    // the other as the scene has it.
    double seen_max = 0, unseen_max = 0;
    for (size_t k = 0; k < tl.scans.size(); ++k)
        for (size_t b = 0; b < tl.beams.size(); ++b)
            seen_max = std::max(seen_max, double(tl.column[k][b])),
            unseen_max = std::max(unseen_max, double(tl.column_unseen[k][b]));
    EXPECT_GT(seen_max, 0.007) << "the first cloud, on the camera's line";
    EXPECT_GT(unseen_max, 0.007) << "the second cloud, out of the camera's view";
    EXPECT_LE(tl_error, 0.15);
    EXPECT_EQ(dt.shape, SmokeShape::Timeline);
    ASSERT_EQ(dt.findings.size(), 1u) << findingsText(dt);
    EXPECT_EQ(dt.findings[0].cause, "surface_range_bias");
    EXPECT_EQ(dt.findings[0].target, "target_a");
    const Estimate e = dt.findings[0].parameters.front().second;
    EXPECT_LE(std::abs(e.value - beta), 3 * e.se) << findingsText(dt);
    EXPECT_LE(e.se, 0.05 * beta) << "a bias this large is measured to 5 %";
}
