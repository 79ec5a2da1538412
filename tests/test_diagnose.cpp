// The diagnosis finds what was planted, by its own mechanism, into simulated runs: the right cause
// and target at a stated magnitude, over random seeds; and names nothing on clean runs.
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>

#include "diagnose/candidate_fit.hpp"
#include "diagnose/candidates.hpp"
#include "diagnose/causes.hpp"
#include "diagnose/replay_model.hpp"
#include "normal_cdf.hpp"
#include "plant.hpp"
#include "smokescan/core/random.hpp"
#include "smokescan/diagnose/diagnosis.hpp"
#include "smokescan/diagnose/diagnosis_report.hpp"

using namespace smokescan;
using namespace smokescan::test;
using smokescan::detail::Cause;
using smokescan::detail::causeName;
using smokescan::detail::kCauses;

namespace {

/// Seeds per test: one under the sanitizers.
int seeds(int n) { return sanitized() ? 1 : n; }

/// The statistical tests that the sanitizer build leaves to the Release build (one planted run
/// and the three-effect run cover the code paths there).
#define SKIP_WHEN_SANITIZED() \
    if (sanitized()) GTEST_SKIP() << "statistics over seeds: checked in the Release build"

DiagnosisResult diagnoseRun(const TrueRun& r, double offset_s = 0, double block_s = 3)
{
    const FitInputs in = inputsOf(r);
    ReplayConfig rc;
    rc.offset_s = offset_s;
    rc.block_s = block_s;
    const Replay replay = replayRun(in, in.mount.config, rc);
    return diagnose(replay);
}

bool found(const DiagnosisResult& d, const std::string& cause, const std::string& target = "")
{
    for (const auto& f : d.findings)
        if (f.cause == cause && (target.empty() || f.target == target)) return true;
    return false;
}

const Finding* finding(const DiagnosisResult& d, const std::string& cause, const std::string& target = "")
{
    for (const auto& f : d.findings)
        if (f.cause == cause && (target.empty() || f.target == target)) return &f;
    return nullptr;
}

std::string describe(const DiagnosisResult& d) { return "verdict: " + findingsText(d); }

/// One planted cause: its name, target, and the value the diagnosis should report.
struct Planted {
    std::string cause, target, parameter;
    double value = 0;
};

/// Plants cause `which` at a random magnitude above its stated detectability into run r.
Planted plantCause(int which, TrueRun& r, uint64_t seed)
{
    KeyedRng rng(seed, 4242, uint64_t(which));
    const double P = bocasWorld().scene.sensors[0].config.paper.penetration_power;
    auto smokeError = [](const BeamView& v) {
        return v.truth.error && std::string(v.truth.cause) == "penetration_power";
    };
    switch (which) {
    case 0: {  // the gold paper reads long as smoke thickens: 5.6–14 % at the threshold
        const double beta = 8 + 12 * rng.uniform();
        plant(r, [&](BeamView& v) {
            if (v.surface == "target_gold" && !v.truth.error)
                v.value = std::llround(double(v.value) * (1 + beta * v.column));
        });
        return {"surface_range_bias", "target_gold", "bias_per_column_per_density_m", beta};
    }
    case 1: {  // the yellow paper fails at a 35–70 % higher or 25–40 % lower column
        const double f = rng.uniform() < 0.5 ? 1.35 + 0.35 * rng.uniform() : 0.6 + 0.15 * rng.uniform();
        plant(r, [&](BeamView& v) {
            if (v.surface != "target_yellow" || !v.truth.hit.hit) return;
            const bool err = v.column > P * f;
            if (err && !v.truth.error) v.value = 0;
            if (!err && smokeError(v)) v.value = surfaceReading(r, v, rng);
        });
        return {"surface_threshold", "target_yellow", "ln_threshold_factor", std::log(f)};
    }
    case 2: {  // a gradual onset: width 0.15–0.3 in ln(column)
        const double w = 0.15 + 0.15 * rng.uniform();
        plant(r, [&](BeamView& v) {
            if (!v.truth.hit.hit || !(v.column > 0) || (v.truth.error && !smokeError(v))) return;
            const bool err = rng.uniform() < normalCdf((std::log(v.column) - std::log(P)) / w);
            if (err)
                v.value = 0;
            else if (smokeError(v))
                v.value = surfaceReading(r, v, rng);
        });
        return {"threshold_width", "", "width_ln_column", w};
    }
    case 3: {  // range noise growing with the column: 3–6 m per density·m
        const double g = 3 + 3 * rng.uniform();
        plant(r, [&](BeamView& v) {
            if (!v.truth.error) v.value += std::llround(g * v.column * rng.normal() / r.spec.unit_m);
        });
        return {"range_noise_growth", "", "noise_growth_m_per_density_m", g};
    }
    case 4: {  // 25–45 % of the smoke failures return a short range instead
        const double q = 0.25 + 0.2 * rng.uniform();
        plant(r, [&](BeamView& v) {
            if (smokeError(v) && v.truth.hit.hit && rng.uniform() < q)
                v.value = std::llround((0.1 + (v.truth.hit.t_m - 0.1) * rng.uniform()) / r.spec.unit_m);
        });
        return {"smoke_obstacle_return", "", "short_return_share", q};
    }
    case 5: {  // a dirty window: beams between −50° and −35° fail 30–60 % of the time
        const double d = 0.3 + 0.3 * rng.uniform();
        plant(r, [&](BeamView& v) {
            const double deg = v.angle_rad * 180 / M_PI;
            if (deg >= -50 && deg <= -35 && v.truth.hit.hit && rng.uniform() < d) v.value = 0;
        });
        return {"sector_dropout", "", "dropout", d};
    }
    case 6: {  // the onset while smoke falls lies 0.5–0.8 higher in ln(column) than while it rises
        const double h = 0.5 + 0.3 * rng.uniform();
        plant(r, [&](BeamView& v) {
            if (!v.truth.hit.hit || (v.truth.error && !smokeError(v))) return;
            const bool rising = v.column > v.previous_column;
            const bool err = v.column > P * std::exp(rising ? -0.5 * h : 0.5 * h);
            if (err && !v.truth.error) v.value = 0;
            if (!err && smokeError(v)) v.value = surfaceReading(r, v, rng);
        });
        return {"hysteresis", "", "ln_threshold_falling_over_rising", h};
    }
    }
    return {};
}

/// The causes plantCause plants, by its index (which also keys each cause's seeds).
const Cause kPlanted[] = {Cause::SurfaceRangeBias, Cause::SurfaceThreshold,    Cause::ThresholdWidth,
                          Cause::RangeNoiseGrowth, Cause::SmokeObstacleReturn, Cause::SectorDropout,
                          Cause::Hysteresis};

/// What planting one cause into seeds gave: how often it was found, the pulls of its magnitude,
/// and the runs that named something else beside it.
struct FoundStats {
    int runs = 0, found = 0, with_extra = 0;
    double max_error = 0;  ///< the largest |found − planted| (clock offset) [s]
    std::vector<double> pulls;
    std::string extras;
};

/// Plants cause `which` into `n` seeds (from `first`); each must be found with its target, and its
/// magnitude within 3 of its reported standard errors (plus 5 %).
FoundStats expectFound(int which, int n, uint64_t first = 0, bool each = true)
{
    FoundStats st;
    for (int s = 0; s < n; ++s) {
        const uint64_t seed = 100 * uint64_t(which + 1) + first + uint64_t(s);
        TrueRun r = simulateBocas(seed);
        const Planted p = plantCause(which, r, seed);
        EXPECT_EQ(p.cause, causeName(kPlanted[which])) << "the planter and the list of causes are out of step";
        const DiagnosisResult d = diagnoseRun(r);
        ++st.runs;
        bool extra = false;
        for (const auto& f : d.findings) extra |= !(f.cause == p.cause && (p.target.empty() || f.target == p.target));
        if (extra) {
            ++st.with_extra;
            st.extras += "seed " + std::to_string(seed) + ": " + describe(d) + "\n";
        }
        if (each)
            EXPECT_TRUE(found(d, p.cause, p.target)) << p.cause << " " << p.value << " seed " << seed << "\n"
                                                     << describe(d);
        if (!found(d, p.cause, p.target)) continue;
        ++st.found;
        const Finding* f = finding(d, p.cause, p.target);
        bool reported = false;
        for (const auto& [name, e] : f->parameters)
            if (name == p.parameter) {
                reported = true;
                EXPECT_NEAR(e.value, p.value, 3 * e.se + 0.05 * std::abs(p.value)) << p.cause << " seed " << seed;
                st.pulls.push_back((e.value - p.value) / e.se);
            }
        EXPECT_TRUE(reported) << p.cause << " reports no " << p.parameter;
        if (p.cause == "sector_dropout")  // the planted sector, −50° to −35°, within a beam's width
            EXPECT_EQ(f->target, "sector -50.1..-35.0 deg") << "seed " << seed;
    }
    // Beside the planted cause, another is named in at most one run of four (the level allows
    // one false alarm in twenty rounds; a planted effect may also leave a small misfit behind).
    if (each) EXPECT_LE(st.with_extra, std::max(1, n / 4)) << st.extras;
    return st;
}

/// The camera's clock 4–8 s ahead of the laser's, in `n` seeds from `first`: found, to about ±0.5 s.
FoundStats expectClockOffsetFound(int n, uint64_t first, bool each = true)
{
    FoundStats st;
    for (int s = 0; s < n; ++s) {
        const uint64_t seed = first + uint64_t(s);
        KeyedRng rng(seed, 17);
        const double delta = 4 + 4 * rng.uniform();
        // Blocks of 2 s: the offset's evidence lies in the smoke's rises and falls (three in a BOCAS
        // run), and the sign-flip test needs enough blocks there (docs/diagnosis.md, known limits).
        const DiagnosisResult d = diagnoseRun(simulateBocas(seed, 360, 1, 0.01, delta), 0, 2.0);
        ++st.runs;
        st.with_extra += d.findings.size() > (found(d, "clock_offset") ? 1u : 0u);
        std::string tried;
        for (const auto& t : d.tried)
            if (t.cause == "clock_offset")
                tried += " round " + std::to_string(t.round) + ": gain " + std::to_string(t.loglik_gain) + " p " +
                    std::to_string(t.p_value);
        if (each) EXPECT_TRUE(found(d, "clock_offset")) << delta << "\n" << describe(d) << "\ntried" << tried;
        if (!found(d, "clock_offset")) continue;
        ++st.found;
        const Estimate e = finding(d, "clock_offset")->parameters.front().second;
        // Found to about ±0.5 s (up to 0.71 s low over the long suite's 20 seeds): the likelihood
        // is rugged at the camera's 0.2 s frame steps and the replay itself lags; the reported
        // error (the curvature's) understates that (docs/diagnosis.md: known limits). The long
        // suite records the errors rather than asserting them.
        if (each) EXPECT_NEAR(e.value, delta, 3 * e.se + 0.6) << "seed " << seed;
        st.pulls.push_back((e.value - delta) / e.se);
        st.max_error = std::max(st.max_error, std::abs(e.value - delta));
    }
    return st;
}

/// Clean runs of `n` seeds from `first` in blocks of block_s: how many named a cause (their
/// verdicts in `seen`).
int cleanNamed(int n, uint64_t first, std::string& seen, double block_s = 3)
{
    int named = 0;
    for (int s = 0; s < n; ++s) {
        const DiagnosisResult d = diagnoseRun(simulateBocas(first + uint64_t(s)), 0, block_s);
        if (!d.findings.empty()) {
            ++named;
            seen += describe(d) + "\n";
        }
    }
    return named;
}

}  // namespace

TEST(CauseTable, EveryCauseHasOneRowAndItsOwnName)
{
    // The table is the one place a cause is written: each cause of the enum has exactly one row,
    // found by its public name; each row has starts for its fit, every function, a floor and a
    // covariate the report knows.
    std::set<std::string> names;
    for (Cause c : kCauses) {
        const smokescan::detail::CauseRow& row = smokescan::detail::causeRow(c);
        EXPECT_TRUE(names.insert(row.name).second) << row.name << " twice";
        EXPECT_NE(row.apply, nullptr) << row.name;
        EXPECT_NE(row.commit, nullptr) << row.name;
        EXPECT_NE(row.report, nullptr) << row.name;
        EXPECT_NE(row.effect, nullptr) << row.name;
        EXPECT_GT(row.floor, 0) << row.name << ": a floor of 0 names every significant misfit";
        EXPECT_NE(row.floor_unit, nullptr) << row.name;
        EXPECT_EQ(smokescan::detail::causeRow(row.name), &row);
        EXPECT_FALSE(row.starts.empty()) << row.name;
        EXPECT_NO_THROW(smokescan::residualsBy(smokescan::Replay{}, {}, row.covariate)) << row.name;
    }
    EXPECT_EQ(smokescan::detail::causeRow("no_such_cause"), nullptr);
}

/// Whether two Jets are the same doubles (a value NaN in both counts as the same; ±0 alike).
bool sameDoubles(const smokescan::detail::J& a, const smokescan::detail::J& b)
{
    const bool value = a.a == b.a || (std::isnan(a.a) && std::isnan(b.a));
    const bool slope = a.v[0] == b.v[0] || (std::isnan(a.v[0]) && std::isnan(b.v[0]));
    return value && slope;
}

/// Every observation's ln L and its derivative with and without one memo per observation, kept
/// through every cause's starts (each twice: the memo's values reused; and a step away: its
/// inputs moved), model after model (each moving one of the memo's inputs without a derivative). Returns how many differ;
/// `kept` counts the memo's slots that hold both values at the end.
long memoMismatches(const smokescan::Replay& replay, long& kept)
{
    using namespace smokescan::detail;
    // Models that each move one of the memo's inputs: the column (a clock offset: the smoke read at
    // other times, and with it the width its error sets), ln P (a threshold factor), the width,
    // the reading's mean (a range bias) and its variance (a noise growth).
    std::vector<smokescan::ModelExtensions> ext(6);
    ext[1].clock_offset_s = 1.5;
    const int seen = replay.beams[replay.beams.size() / 2].surface;  // the surface ahead
    ext[2].surfaces[replay.surface_names[size_t(seen)]].threshold_factor = 0.3;
    ext[3].threshold_width = 0.2;
    ext[4].surfaces[replay.surface_names[size_t(seen)]].range_bias = 10;
    ext[5].range_noise_growth_m = 2;
    std::vector<ReplayModel> models;
    for (const auto& e : ext) models.emplace_back(replay, e);
    std::vector<const ReplayModel*> order;  // base, one moved, base, another moved, …: one input at a time
    for (size_t k = 1; k < models.size(); ++k) order.insert(order.end(), {&models[0], &models[k]});
    Candidate all;
    all.cause = Cause::ClockOffset;
    const std::vector<Obs> every = touched(replay, all, -1);
    // 3000 spread over the run (its smoke comes and goes); 600 under the sanitizers (their part
    // is the memory, and the 30 s a unit test has).
    const size_t spread = sanitized() ? 600 : 3000;
    std::vector<Obs> obs;
    for (size_t i = 0; i < every.size(); i += std::max<size_t>(1, every.size() / spread)) obs.push_back(every[i]);
    std::vector<ObsMemo> memo(obs.size());
    long bad = 0;
    for (Cause cause : kCauses)
        for (const ReplayModel* model : order) {
            const ReplayModel& m = *model;
            Candidate c;
            c.cause = cause;
            c.surface = seen;
            c.from_rad = replay.beams[100].angle_rad, c.to_rad = replay.beams[300].angle_rad;
            const std::vector<double>& starts = c.starts();
            const size_t n = std::min<size_t>(3, starts.size());  // three at most, first to last
            for (size_t s = 0; s < n; ++s) {
                const double start = starts[n > 1 ? s * (starts.size() - 1) / (n - 1) : 0];
                for (double theta : {start, start, start + 1e-3}) {
                    const CandidateAt at(replay, m, c, J(theta, 0));
                    for (size_t i = 0; i < obs.size(); ++i)
                        bad += !sameDoubles(at.logLik(obs[i]), at.logLik(obs[i], &memo[i]));
                }
            }
        }
    kept = 0;  // slots holding a p_s and a reading's density
    for (const ObsMemo& o : memo) kept += !std::isnan(o.density) && !std::isnan(o.stop);
    return bad;
}

TEST(CandidateLikelihood, TheMemoGivesTheDoublesOfRecomputingThem)
{
    // ObsMemo reuses what θ did not move; it must change no double of any fit, paper or
    // physical model, for any cause: a memo that missed one of its inputs, or reused a value
    // whose inputs moved without a derivative (another model), fails here.
    const TrueRun r = simulateBocas(5, 60, 1);
    const FitInputs in = inputsOf(r);
    for (SensorModel model : {SensorModel::Paper, SensorModel::Physical}) {
        SensorConfig config = in.mount.config;
        config.model = model;
        long kept = 0;
        EXPECT_EQ(memoMismatches(replayRun(in, config, ReplayConfig{}), kept), 0) << int(model);
        EXPECT_GT(kept, sanitized() ? 400 : 2000) << "the memo was not used";
    }
}

/// A replay in clear air: 40 beams 0.01 rad apart on one wall at 3 m, 200 scans in 10 blocks;
/// beam b errs in scan k with probability share(b).
template <class Share>
smokescan::Replay clearAirReplay(Share share)
{
    smokescan::Replay r;
    r.config.model = smokescan::SensorModel::Paper;
    r.config.paper.penetration_power = 0.007;
    r.spec.dangle_rad = 0.01;
    r.surface_names = {"wall"};
    r.from_saturation = false;
    for (int b = 0; b < 40; ++b) {
        smokescan::ReplayBeam beam;
        beam.surface = 0;
        beam.range_m = beam.sight_m = 3;
        beam.angle_rad = -0.2 + 0.01 * b;
        beam.column_ref = 0.005;
        beam.sigma_m = 0.01;
        r.beams.push_back(beam);
    }
    smokescan::KeyedRng rng(7, 0);
    for (int k = 0; k < 200; ++k) {
        smokescan::ReplayScan scan;
        scan.time_s = 0.5 * k;
        scan.block = k / 20;
        r.scans.push_back(scan);
        r.column.emplace_back(40, 0.0f);
        std::vector<float> ranges;
        for (int b = 0; b < 40; ++b) ranges.push_back(rng.uniform() < share(b) ? NAN : float(3 + 0.01 * rng.normal()));
        r.range_m.push_back(ranges);
    }
    return r;
}

TEST(SectorSearch, FindsTheExcessOverWhatTheModelExpectsInClearAir)
{
    // The model already expects 20 % dropout over beams 10–25 (a sector a sensor file holds, or
    // the physical model's clear-air errors on a near wall); beams 14–18 fail 60 %. The search
    // must see the excess there, and nothing where the record is what the model expects.
    using smokescan::detail::ReplayModel;
    smokescan::ModelExtensions known;
    const double deg = 180 / M_PI;
    known.sectors.push_back({(-0.2 + 0.095) * deg, (-0.2 + 0.255) * deg, 0.2});
    auto within = [](int b, int lo, int hi) { return b >= lo && b <= hi; };
    const auto planted = clearAirReplay([&](int b) { return within(b, 14, 18) ? 0.6 : within(b, 10, 25) ? 0.2 : 0.0; });
    const auto expected = clearAirReplay([&](int b) { return within(b, 10, 25) ? 0.2 : 0.0; });
    double from = 0, to = 0;
    ASSERT_TRUE(smokescan::detail::findDropoutSector(planted, ReplayModel(planted, known), -1, from, to));
    EXPECT_NEAR(from, -0.2 + 0.135, 1e-9);  // beam 14's lower edge
    EXPECT_NEAR(to, -0.2 + 0.185, 1e-9);  // beam 18's upper edge
    EXPECT_FALSE(smokescan::detail::findDropoutSector(expected, ReplayModel(expected, known), -1, from, to));
    // Without the known sector, the whole of 10–25 is the excess.
    ASSERT_TRUE(smokescan::detail::findDropoutSector(expected, ReplayModel(expected, {}), -1, from, to));
    EXPECT_NEAR(from, -0.2 + 0.095, 1e-9);
    EXPECT_NEAR(to, -0.2 + 0.255, 1e-9);
}

namespace {

/// A replay in smoke of a sharp-edged or narrow threshold: 40 beams on one wall at 3 m, 200
/// scans in 10 blocks; each beam's column is the penetration power P times e^u, u uniform on
/// ±0.6, and it errs with probability Φ(u/w) (w = 0: when u > 0). The camera's density is
/// uncertain by `ln_sd` in ln (the model's width is at least that).
smokescan::Replay thresholdReplay(double w, double ln_sd)
{
    smokescan::Replay r = clearAirReplay([](int) { return 0.0; });
    smokescan::KeyedRng rng(11, 0);
    for (size_t k = 0; k < r.scans.size(); ++k) {
        r.scans[k].ln_density_sd = ln_sd;
        for (size_t b = 0; b < r.beams.size(); ++b) {
            const double u = -0.6 + 1.2 * rng.uniform();
            r.column[k][b] = float(0.007 * std::exp(u));
            const double p = w > 0 ? normalCdf(u / w) : double(u > 0);
            r.range_m[k][b] = rng.uniform() < p ? NAN : float(3 + 0.01 * rng.normal());
        }
    }
    return r;
}

/// The threshold width's fit on a replay, and the argmax of the same likelihood on a grid 0.02
/// apart over θ = ln w in [−20, 2].
struct WidthFit {
    smokescan::detail::ThetaFit fit;
    double brute_theta = NAN;
};

WidthFit fitWidth(const smokescan::Replay& r)
{
    using namespace smokescan::detail;
    const ReplayModel m(r, {});
    Candidate c;
    c.cause = Cause::ThresholdWidth;
    const std::vector<Obs> obs = touched(r, c, -1);
    WidthFit f{fitCandidate(r, m, c, obs)};
    double best = -INFINITY;
    for (double theta = -20; theta <= 2; theta += 0.02) {
        const CandidateAt at(r, m, c, J(theta, 0));
        double ll = 0;
        for (const Obs& o : obs) ll += at.logLik(o).a;
        if (ll > best) best = ll, f.brute_theta = theta;
    }
    return f;
}

}  // namespace

TEST(CandidateFit, AWidthWhoseBestIsZeroEndsAtItsNilAndOneBelowTheLowestStartIsFound)
{
    // A threshold with a sharp edge, the camera's density uncertain by 0.05 in ln: the model's
    // width is at least that, the width's best is the boundary, and the fit must reach its row's
    // nil (ln w = −16; walking there, it stopped on the way). A narrow one (w = 0.003, ln w
    // −5.8, below the lowest start ln 0.05) with the density known: the nil costs less than the
    // lowest start and the gradient there underflows to zero, but the optimum lies between, where
    // the fit must find it (the argmax of the same likelihood on a grid).
    using smokescan::detail::causeRow;
    const double nil = causeRow(Cause::ThresholdWidth).nil_below;
    const WidthFit sharp = fitWidth(thresholdReplay(0, 0.05));
    ASSERT_TRUE(sharp.fit.ok);
    EXPECT_LE(sharp.fit.theta, nil);
    EXPECT_LE(sharp.brute_theta, nil) << "the likelihood itself rises to the boundary";
    const WidthFit narrow = fitWidth(thresholdReplay(0.003, 0));
    ASSERT_TRUE(narrow.fit.ok);
    EXPECT_LT(narrow.brute_theta, std::log(0.05) - 0.5) << "the optimum lies below the lowest start";
    EXPECT_NEAR(narrow.fit.theta, narrow.brute_theta, 0.02);
    EXPECT_LT(std::abs(narrow.fit.theta - std::log(0.003)), 3 * narrow.fit.se) << narrow.fit.se;
}

TEST(CandidateFit, ItsErrorIsTheSandwichOfTheLikelihoodsOwnCurvatureAndBlockScores)
{
    // A width of 0.1 (an optimum inside the starts): the fit's standard error against the same
    // cluster-robust sandwich computed by brute force at the fitted θ: the curvature from a
    // second difference of the log-likelihood's values, each block's score from the exact
    // gradient at θ, the correction B/(B − 1), and never below the model's own 1/information.
    using namespace smokescan::detail;
    const smokescan::Replay r = thresholdReplay(0.1, 0);
    const ReplayModel m(r, {});
    Candidate c;
    c.cause = Cause::ThresholdWidth;
    const std::vector<Obs> obs = touched(r, c, -1);
    const ThetaFit f = fitCandidate(r, m, c, obs);
    ASSERT_TRUE(f.ok);
    EXPECT_NEAR(f.theta, std::log(0.1), 0.5);
    auto ll = [&](double theta) {
        const CandidateAt at(r, m, c, J(theta, 0));
        double sum = 0;
        for (const Obs& o : obs) sum += at.logLik(o).a;
        return sum;
    };
    const double h = 1e-3, info = -(ll(f.theta + h) - 2 * ll(f.theta) + ll(f.theta - h)) / (h * h);
    ASSERT_GT(info, 0);
    std::map<int, double> score;
    const CandidateAt at(r, m, c, J(f.theta, 0));
    for (const Obs& o : obs) score[r.scans[size_t(o.k)].block] += at.logLik(o).v[0];
    double meat = 0;
    for (const auto& [block, sc] : score) meat += sc * sc;
    const double B = double(score.size());
    ASSERT_GE(B, 10);
    const double se = std::sqrt(std::max(1 / info, B / (B - 1) * meat / (info * info)));
    EXPECT_NEAR(f.se, se, 0.01 * se) << "brute force: information " << info << ", meat " << meat;
}

TEST(Diagnose, CleanRunsNameNothing)
{
    SKIP_WHEN_SANITIZED();
    // 20 seeds of the plain BOCAS run: the verdict is `none` in all but at most one (5 %; the
    // test's level is 5 % a round). The long suite (DiagnoseLong) runs 100.
    const int n = seeds(20);
    std::string seen;
    EXPECT_LE(cleanNamed(n, 900, seen), std::max(1, n / 20)) << seen;
}

/// Each cause of the library's list (but the clock offset, which has its own test below) is
/// planted into four seeds and must be found with its target and magnitude. A cause added to the
/// library without a planter here fails.
class DiagnosePlanted : public ::testing::TestWithParam<Cause> {};

TEST_P(DiagnosePlanted, IsFound)
{
    const Cause c = GetParam();
    const auto it = std::find(std::begin(kPlanted), std::end(kPlanted), c);
    ASSERT_NE(it, std::end(kPlanted)) << "no planter for cause " << causeName(c);
    // Under the sanitizers one planted run covers the code paths; the statistics are the Release build's.
    if (c != Cause::SurfaceRangeBias) SKIP_WHEN_SANITIZED();
    expectFound(int(it - std::begin(kPlanted)), seeds(4));
}

std::vector<Cause> plantedCauses()
{
    std::vector<Cause> out;
    for (Cause c : kCauses)
        if (c != Cause::ClockOffset) out.push_back(c);
    return out;
}

INSTANTIATE_TEST_SUITE_P(Diagnose, DiagnosePlanted, ::testing::ValuesIn(plantedCauses()),
                         [](const ::testing::TestParamInfo<Cause>& i) { return std::string(causeName(i.param)); });

TEST(Diagnose, ClockOffsetIsFound)
{
    SKIP_WHEN_SANITIZED();
    expectClockOffsetFound(seeds(4), 800);
}

TEST(Diagnose, ThreeEffectsTogetherAreAllFound)
{
    SKIP_WHEN_SANITIZED();  // one planted run (SurfaceRangeBiasIsFound) and the CLI's cover the paths
    for (int s = 0; s < seeds(2); ++s) {
        const uint64_t seed = 1700 + uint64_t(s);
        TrueRun r = simulateBocas(seed);
        const Planted a = plantCause(0, r, seed), b = plantCause(5, r, seed), c = plantCause(1, r, seed);
        const DiagnosisResult d = diagnoseRun(r);
        for (const Planted* p : {&a, &b, &c})
            EXPECT_TRUE(found(d, p->cause, p->target)) << p->cause << "\n" << describe(d);
    }
}

// Deterministic for a seed whatever the thread count: the replay and every round's fits, held-out
// gains and sign-flip tests on one thread and on four give the same report to the byte.
TEST(Diagnose, TheReportIsTheSameOnOneThreadAndOnFour)
{
    SKIP_WHEN_SANITIZED();  // two whole diagnoses: the Release build's
    TrueRun r = simulateBocas(1750);
    const Planted a = plantCause(0, r, 1750), b = plantCause(4, r, 1750);
    // "All" as four threads whatever the machine has (on one core the two runs would be one).
    std::string all;
    {
        tbb::global_control four(tbb::global_control::max_allowed_parallelism, 4);
        tbb::task_arena arena(4);
        arena.execute([&] { all = diagnosisJson(diagnoseRun(r), {}); });
    }
    std::string one;
    {
        tbb::global_control only(tbb::global_control::max_allowed_parallelism, 1);
        one = diagnosisJson(diagnoseRun(r), {});
    }
    EXPECT_EQ(one, all);
    EXPECT_NE(all.find('"' + a.cause + '"'), std::string::npos) << all;  // a report with findings
    EXPECT_NE(all.find('"' + b.cause + '"'), std::string::npos) << all;
}

TEST(DiagnosisReport, EveryInputsNameIsWrittenEscapedWhateverItsBytes)
{
    // Each input named with a byte that is not UTF-8 and a line break: the JSON is valid and names
    // each escaped, whole (the JSON writer would throw on the raw byte after all the work).
    DiagnosisSources src{"laser\xff.log", "sat\nurated.csv", "scene\xfe.toml", "calib\x01.json", "sensor\xc3.toml"};
    DiagnosisResult r;
    r.verdict = "none";
    const nlohmann::json j = nlohmann::json::parse(diagnosisJson(r, src));
    EXPECT_EQ(j["inputs"]["laser"], "laser\\xFF.log");
    EXPECT_EQ(j["inputs"]["saturation"], "sat\\x0Aurated.csv");
    EXPECT_EQ(j["inputs"]["scene"], "scene\\xFE.toml");
    EXPECT_EQ(j["inputs"]["calibration"], "calib\\x01.json");
    EXPECT_EQ(j["inputs"]["sensor_file"], "sensor\\xC3.toml");
}

TEST(Diagnose, BelowDetectabilityIsNotClaimed)
{
    SKIP_WHEN_SANITIZED();
    // The gold reading 0.007 % long at the threshold (β = 0.01, under one standard error of its
    // fit over a BOCAS run, about 0.03): named in at most one run of eight.
    const int n = seeds(8);
    int named = 0;
    for (int s = 0; s < n; ++s) {
        TrueRun r = simulateBocas(2000 + uint64_t(s));
        plant(r, [&](BeamView& v) {
            if (v.surface == "target_gold" && !v.truth.error)
                v.value = std::llround(double(v.value) * (1 + 0.01 * v.column));
        });
        named += found(diagnoseRun(r), "surface_range_bias");
    }
    EXPECT_LE(named, std::max(1, n / 10));
}

TEST(Diagnose, EffectsOfAnotherFormAreNamed)
{
    SKIP_WHEN_SANITIZED();
    // Mechanisms the candidates do not assume: the gold's lengthening saturates with the column
    // (up to +12 %, a tanh, not a line through zero), and a smudge on the window whose dropout falls
    // off smoothly (a cos² bump from −60° to −30°, 70 % at its centre −45°, not a box).
    const double P = bocasWorld().scene.sensors[0].config.paper.penetration_power;
    for (int s = 0; s < seeds(3); ++s) {
        const uint64_t seed = 2600 + uint64_t(s);
        TrueRun r = simulateBocas(seed);
        KeyedRng rng(seed, 5);
        plant(r, [&](BeamView& v) {
            if (v.surface == "target_gold" && !v.truth.error)
                v.value = std::llround(double(v.value) * (1 + 0.12 * std::tanh(1.5 * v.column / P)));
            const double deg = v.angle_rad * 180 / M_PI;
            if (deg > -60 && deg < -30 && v.truth.hit.hit) {
                const double c = std::cos((deg + 45) / 15 * M_PI / 2);
                if (rng.uniform() < 0.7 * c * c) v.value = 0;
            }
        });
        const DiagnosisResult d = diagnoseRun(r);
        EXPECT_TRUE(found(d, "surface_range_bias", "target_gold")) << describe(d);
        const Finding* f = finding(d, "sector_dropout");
        ASSERT_NE(f, nullptr) << describe(d);
        double a = 0, b = 0;
        ASSERT_EQ(std::sscanf(f->target.c_str(), "sector %lf..%lf deg", &a, &b), 2) << f->target;
        EXPECT_GE(a, -61.0) << f->target;  // within the smudge, over its centre
        EXPECT_LE(b, -29.0) << f->target;
        EXPECT_LT(a, -45.0) << f->target;
        EXPECT_GT(b, -45.0) << f->target;
    }
}

TEST(DiagnoseLong, RatesOverManySeeds)
{
    if (!std::getenv("SMOKESCAN_LONG_TESTS"))
        GTEST_SKIP() << "set SMOKESCAN_LONG_TESTS=1 (about 30 min on 2 cores): the rates in docs/diagnosis.md";
    // Each cause planted into 20 seeds (not the short suite's), the clock offset too, and 100 clean
    // runs. The rates the issue asks for: found ≥ 95 %, clean runs named ≤ 5 %.
    std::printf("| cause | found | runs with another finding | pulls within 1 se | within 2 se | pull sd |\n");
    auto row = [](const std::string& name, const FoundStats& st) {
        double m = 0, m2 = 0;
        int in1 = 0, in2 = 0;
        for (double x : st.pulls) {
            m += x;
            m2 += x * x;
            in1 += std::abs(x) < 1;
            in2 += std::abs(x) < 2;
        }
        const double n = std::max<double>(1, double(st.pulls.size()));
        std::printf("| %s | %d/%d | %d | %.2f | %.2f | %.2f |\n", name.c_str(), st.found, st.runs, st.with_extra,
                    in1 / n, in2 / n, std::sqrt(std::max(0.0, m2 / n - (m / n) * (m / n))));
        EXPECT_GE(st.found, int(std::ceil(0.95 * st.runs))) << name;
        EXPECT_LE(st.with_extra, int(std::ceil(0.1 * st.runs))) << name << "\n" << st.extras;
    };
    for (int which = 0; which < 7; ++which) row(causeName(kPlanted[which]), expectFound(which, 20, 50, false));
    const FoundStats clock = expectClockOffsetFound(20, 3000, false);
    row("clock_offset", clock);
    std::printf("clock offset: largest error %.2f s\n", clock.max_error);
    std::string seen;
    const int named = cleanNamed(100, 5000, seen);
    std::printf("clean runs naming a cause: %d/100\n%s", named, seen.c_str());
    EXPECT_LE(named, 5) << seen;
    seen.clear();
    const int named2 = cleanNamed(40, 7000, seen, 2.0);  // the clock-offset test's blocks
    std::printf("clean runs in 2 s blocks naming a cause: %d/40\n%s", named2, seen.c_str());
    EXPECT_LE(named2, 2) << seen;
}

TEST(Diagnose, ExploreMagnitudes)
{
    if (!std::getenv("SMOKESCAN_EXPLORE")) GTEST_SKIP() << "exploration only";
    if (std::getenv("SMOKESCAN_EXPLORE_COMBO")) {
        TrueRun r = simulateBocas(1700);
        plantCause(0, r, 1700), plantCause(5, r, 1700), plantCause(1, r, 1700);
        const DiagnosisResult d = diagnoseRun(r);
        std::printf("combo: %s\n", describe(d).c_str());
        for (const auto& t : d.tried)
            if (t.loglik_gain > 20)
                std::printf("   tried %d %s %s gain %.1f p %.2g\n", t.round, t.cause.c_str(), t.target.c_str(),
                            t.loglik_gain, t.p_value);
        KeyedRng crng(801, 17);
        const double cd = 4 + 4 * crng.uniform();
        std::printf("clock planted %.3f\n", cd);
        const DiagnosisResult c = diagnoseRun(simulateBocas(801, 360, 1, 0.01, cd));
        std::printf("clock: %s\n", describe(c).c_str());
        for (const auto& t : c.tried)
            if (t.loglik_gain > 20 || t.cause == "clock_offset")
                std::printf("   tried %d %s %s gain %.1f p %.2g\n", t.round, t.cause.c_str(), t.target.c_str(),
                            t.loglik_gain, t.p_value);
        return;
    }
    const int only = std::getenv("SMOKESCAN_EXPLORE_CAUSE") ? std::atoi(std::getenv("SMOKESCAN_EXPLORE_CAUSE")) : -1;
    for (uint64_t seed = 1; seed <= 2; ++seed) {
        TrueRun r = simulateBocas(seed);
        for (int which = 0; which < 7; ++which) {
            if (only >= 0 && which != only) continue;
            TrueRun rr = r;
            const Planted p = plantCause(which, rr, seed);
            const DiagnosisResult d = diagnoseRun(rr);
            std::printf("seed %llu %s %.3f: %s\n", (unsigned long long)seed, p.cause.c_str(), p.value,
                        describe(d).c_str());
            if (std::getenv("SMOKESCAN_EXPLORE_TRIED"))
                for (const auto& t : d.tried)
                    if (t.loglik_gain > 20)
                        std::printf("   tried %d %s %s gain %.1f p %.2g\n", t.round, t.cause.c_str(), t.target.c_str(),
                                    t.loglik_gain, t.p_value);
        }
    }
}
