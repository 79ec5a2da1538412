// Fitting the sensor from recorded data: simulated BOCAS runs with known penetration power, noisy
// saturation and a clock offset are fitted, and every parameter must be recovered within its
// reported uncertainty over many seeds; degenerate runs must be diagnosed, not fitted.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <numeric>
#include <thread>

#include "sanitized.hpp"
#include "smokescan/calib/calibration.hpp"
#include "smokescan/calib/saturation_predict.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/fit/beam_groups.hpp"
#include "smokescan/fit/physical_fit.hpp"
#include "smokescan/fit/plume_fit.hpp"
#include "smokescan/fit/sensor_fit.hpp"
#include "smokescan/media/medium.hpp"
#include "smokescan/scene/scene_io.hpp"
#include "smokescan/sensor_config/urg04lx.hpp"
#include "smokescan/sensors/scanner.hpp"

using namespace smokescan;

namespace {

/// The BOCAS room with its URG-04LX, scans at `rate_hz`.
struct Bocas {
    Scene scene = loadScene("bocas");
    SurfaceSet surfaces{scene};
    CurveFitResult calib = readCalibrationJson("bocas");
    SaturationPredictor predictor{scene, surfaces, calib.curve};
};

Bocas& bocas()
{
    static Bocas b;
    return b;
}

/// The scanner's run as a recorded log: every scan time, values in the sensor's unit as `scan`
/// writes them (mm for the URG and the Sick's mm mode).
RecordedLog logOf(const Scanner& scanner)
{
    RecordedLog log;
    const auto times = scanner.times();
    for (size_t k = 0; k < times.size(); ++k) {
        const Scan s = scanner.scanAt(times[k], k);
        LaserLogScan l;
        l.time_s = s.time_s;
        l.angle_rad = s.angle_rad;
        for (long long v : s.value) l.range.push_back(double(v));
        log.scans.push_back(std::move(l));
    }
    return log;
}

/// A recorded run made by smokescan itself: the scanner's log (mm, as `scan` writes it) on the
/// laser clock, and the predicted target saturation + N(0, sigma_S) on the camera clock, which
/// runs `offset_s` ahead. The scene's smoke timeline is squeezed by `time_scale` when given.
struct SimRun {
    RecordedLog log;
    SaturationSeries sat;
};

SimRun simulate(uint64_t seed, double P, double offset_s, double sigma_S, double from_s = 0, double to_s = 360,
                const std::string& model = "paper", double rate_hz = 2, double camera_hz = 10, double noise_floor = 0)
{
    Bocas& b = bocas();
    Scene scene = b.scene;  // the physical model's noise floor, when given, on a copy
    if (noise_floor > 0) scene.sensors[size_t(scene.findSensor("hokuyo"))].config.physical.noise_floor = noise_floor;
    ScanConfig sc;
    sc.sensor = "hokuyo";
    sc.from_s = from_s;
    sc.to_s = to_s;
    sc.rate_hz = rate_hz;
    sc.seed = seed;
    sc.penetration_power = P;
    sc.model = parseSensorModel(model);
    sc.keep_beams = false;
    const Scanner scanner(scene, b.surfaces, sc);
    SimRun r;
    r.log = logOf(scanner);
    SaturationSimConfig ss;
    ss.from_s = from_s;
    ss.to_s = to_s;
    ss.rate_hz = camera_hz;
    ss.sigma = sigma_S;
    ss.clock_offset_s = offset_s;
    ss.seed = seed + 1000;
    r.sat = simulateSaturation(b.scene, b.predictor, ss);
    return r;
}

std::vector<BeamGroup> targetGroups()
{
    Bocas& b = bocas();
    const SensorMount& m = b.scene.sensors[size_t(b.scene.findSensor("hokuyo"))];
    return beamGroupsFromScene(b.scene, b.surfaces, m, specFor(m.config), "target_");
}

/// The saturation at which the paper model's beams of a group switch: the curve at P / L_i,
/// averaged over the group's beams (the beams' paths differ slightly).
double trueThreshold(const BeamGroup& g, double P)
{
    Bocas& b = bocas();
    const SensorMount& m = b.scene.sensors[size_t(b.scene.findSensor("hokuyo"))];
    const LrfSpec spec = specFor(m.config);
    double sum = 0;
    int n = 0;
    for (int i = 0; i < spec.n_beams; ++i) {
        const double a = spec.angle(i);
        if (!g.contains(a)) continue;
        const Ray ray = m.beamRay(a);
        sum += b.calib.curve(P / b.surfaces.closest(ray, 10).t_m);
        ++n;
    }
    return sum / n;
}

}  // namespace

TEST(BeamGroups, FromSceneFindTheTargetStripsWithoutEdgeBeams)
{
    const auto groups = targetGroups();
    ASSERT_EQ(groups.size(), 3u);
    for (const auto& g : groups) {
        EXPECT_NEAR(g.range_m, 2.51, 0.03) << g.name;
        EXPECT_EQ(g.intervals_rad.size(), 1u) << g.name;
    }
    const BeamGroup parsed = parseBeamGroup("gold=-10.2:-3.5,3.5:4@2.5");
    EXPECT_EQ(parsed.name, "gold");
    EXPECT_DOUBLE_EQ(parsed.range_m, 2.5);
    EXPECT_TRUE(parsed.contains(-5 * M_PI / 180));
    EXPECT_FALSE(parsed.contains(0.0));
    EXPECT_THROW(parseBeamGroup("gold"), Error);
    EXPECT_THROW(parseBeamGroup("gold=1:x"), Error);
}

std::string pulls(const std::vector<double>& v, double* mean, double* sd)
{
    double m = 0, q = 0;
    for (double x : v) m += x;
    m /= double(v.size());
    for (double x : v) q += (x - m) * (x - m);
    *mean = m;
    *sd = std::sqrt(q / double(v.size() - 1));
    return "pulls mean " + std::to_string(m) + " sd " + std::to_string(*sd);
}

// Forty independent simulated runs (paper model, P = 0.007, camera 7.3 s ahead, saturation noise
// 0.01 at 10 Hz, scans at 2 Hz), one strip each so that no two pulls share a saturation series:
// every fitted value within 3.5 of its own standard errors of the truth (S*: 4), and the pulls of S* and of
// the offset centred with a spread in [0.7, 1.3] (the spread's own error is 0.11 at forty). The
// errors come from the fit's parametric bootstrap; the analytic floor it replaced gave S* pulls a
// spread of 0.49 on seeds 1000-1039 and 0.68 on these (docs/fitting.md, "Errors").
TEST(SensorFit, RoundTripPullsOfOffsetAndThresholdHaveUnitSpreadOverIndependentRuns)
{
    const double P = 0.007, offset = 7.3;
    const auto groups = targetGroups();
    std::vector<double> p_off, p_S;
    const uint64_t n = test::sanitized() ? 1 : 40;  // the sanitizers check one run's paths
    for (uint64_t seed = 1; seed <= n; ++seed) {
        const SimRun r = simulate(seed, P, offset, 0.01);
        const SensorFitResult f = fitSensor(r.log, r.sat, groups, urg04lx(), &bocas().calib);
        ASSERT_TRUE(f.ok()) << "seed " << seed << ": "
                            << (f.diagnoses.empty() ? f.thresholds[1].diagnosis : f.diagnoses.front());
        EXPECT_TRUE(f.diagnoses.empty()) << f.diagnoses.front();
        EXPECT_EQ(f.offset.transitions, 2);
        EXPECT_GE(f.offset.bootstrap_fits, 10) << "seed " << seed << ": " << f.error_method;
        EXPECT_NEAR(f.saturation_noise, 0.01, 0.001);
        p_off.push_back((f.offset.offset_s.value - offset) / f.offset.offset_s.se);
        EXPECT_LT(std::abs(p_off.back()), 3.5) << "seed " << seed << " offset " << f.offset.offset_s.value;
        const size_t g = size_t(seed % groups.size());
        const ThresholdFit& th = f.thresholds[g];
        ASSERT_TRUE(th.fitted) << th.group << ": " << th.diagnosis;
        EXPECT_GE(th.bootstrap_fits, 10) << th.group << " seed " << seed << ": " << f.error_method;
        const double S_true = trueThreshold(groups[g], P);
        p_S.push_back((th.S_star.value - S_true) / th.S_star.se);
        // The estimator's tails are heavier than a normal's (seed 4 lies at 3.9 of its error, seed
        // 5 at -2.9): no run beyond 4.
        EXPECT_LT(std::abs(p_S.back()), 4.0) << th.group << " seed " << seed;
        // The paper model's step is sharp: the sensor's own width is consistent with 0.
        EXPECT_LT(th.width.value, 0.004) << th.group;
        EXPECT_LT(std::abs(th.penetration_power.value - P), 3.5 * th.penetration_power.se) << th.group;
    }
    if (n < 40) return;
    double m, sd;
    const std::string off = pulls(p_off, &m, &sd);
    std::printf("offset %s\n", off.c_str());
    EXPECT_LT(std::abs(m), 3 / std::sqrt(double(n))) << "offset " << off;
    EXPECT_GT(sd, 0.7) << "offset " << off;
    EXPECT_LT(sd, 1.3) << "offset " << off;
    const std::string st = pulls(p_S, &m, &sd);
    std::printf("S* %s\n", st.c_str());
    EXPECT_LT(std::abs(m), 3 / std::sqrt(double(n))) << "S* " << st;
    EXPECT_GT(sd, 0.7) << "S* " << st;
    EXPECT_LT(sd, 1.3) << "S* " << st;
}

// The physical model (AMCW URG-04LX, its onset emerging from the lidar equation) with a receiver
// noise floor 1.6 times the calibrated one, camera 2.5 s behind, scans at 1 Hz, sixteen seeds: the noise floor fitted to the
// blue strip's error counts recovers the one the run was made with, within its statistical error
// (the calibration curve's share of the error is systematic: the simulation used the same curve).
// The physical model's error probability has a long two-wave tail, so the probit's P lies below
// the model's own 50 % column; the noise floor fit uses the model's probability and is unbiased.
// Every seed must fit (seed 4, with a sparse error tail on the yellow strip, once sent Fisher
// scoring into a two-cycle; the threshold fit now minimises the deviance itself).
TEST(SensorFit, PhysicalModelRoundTripRecoversTheNoiseFloor)
{
    const double nf_true = 1.6 * physicalDefaults(SensorType::Urg04lx).noise_floor, offset = -2.5;
    const auto groups = targetGroups();
    Bocas& b = bocas();
    const SensorMount& mount = b.scene.sensors[size_t(b.scene.findSensor("hokuyo"))];
    size_t blue = 0;
    while (groups[blue].name != "target_blue") ++blue;
    std::vector<double> pulls_nf;
    const int n = test::sanitized() ? 1 : 16;  // the sanitizers check one run's paths
    for (uint64_t seed = 1; seed <= uint64_t(n); ++seed) {
        const SimRun r = simulate(seed, 0, offset, 0.01, 0, 360, "physical", 1, 10, nf_true);
        const SensorFitResult f = fitSensor(r.log, r.sat, groups, urg04lx(), &b.calib);
        const ThresholdFit& th = f.thresholds[blue];
        ASSERT_TRUE(th.fitted) << "seed " << seed << ": " << th.diagnosis;
        EXPECT_LT(std::abs(f.offset.offset_s.value - offset), 3.5 * f.offset.offset_s.se);
        const UrgNoiseFloorResult nf = fitUrgNoiseFloor(b.scene, b.surfaces, mount, f, blue, b.calib);
        ASSERT_TRUE(nf.ok) << nf.diagnosis;
        EXPECT_GT(nf.se_calibration, 0.0);
        EXPECT_NEAR(nf.noise_floor.se, std::hypot(nf.se_statistical, nf.se_calibration), 1e-12);
        pulls_nf.push_back((nf.noise_floor.value - nf_true) / nf.se_statistical);
        std::printf("seed %d: noise floor %.4g ± %.2g (statistical), truth %.4g\n", int(seed), nf.noise_floor.value,
                    nf.se_statistical, nf_true);
        EXPECT_LT(std::abs(pulls_nf.back()), 3.5) << "seed " << seed << " noise floor " << nf.noise_floor.value;
        // The model's own onset column lies above the probit's P (the two-wave tail).
        EXPECT_GT(nf.onset_column.value, th.penetration_power.value) << "seed " << seed;
    }
    ASSERT_EQ(pulls_nf.size(), size_t(n));
    if (n < 16) return;
    // Sixteen runs: the spread's own error is 0.18, so [0.55, 1.45] fails an error off by half.
    double m, sd;
    const std::string st = pulls(pulls_nf, &m, &sd);
    std::printf("noise floor: %s\n", st.c_str());
    EXPECT_LT(std::abs(m), 3 / std::sqrt(double(n))) << st;
    EXPECT_GT(sd, 0.55) << st;
    EXPECT_LT(sd, 1.45) << st;
}

// A range bias planted on the gold strip, growing as the saturation falls (the paper's gold paper
// reading long), is found with its slope; the strips without it show none.
TEST(SensorFit, FindsAPlantedRangeBiasOnTheGoldStrip)
{
    const double k_m = 0.5;  // bias [m] per unit of saturation drop: 0.25 m (10 %) at S_ref − S = 0.5
    SimRun r = simulate(5, 0.007, 0.0, 0.01);
    const auto groups = targetGroups();
    const BeamGroup* gold = nullptr;
    for (const auto& g : groups)
        if (g.name == "target_gold") gold = &g;
    ASSERT_NE(gold, nullptr);
    const double S_ref = bocas().calib.curve(0.0);
    for (auto& s : r.log.scans) {
        const double S = bocas().predictor.saturation(SmokeField::at(bocas().scene.volumes, s.time_s));
        for (size_t i = 0; i < s.range.size(); ++i)
            if (gold->contains(s.angle_rad[i]) && s.range[i] >= 20) s.range[i] += std::round(1000 * k_m * (S_ref - S));
    }
    SensorFitConfig cfg;
    cfg.clear_quantile = 0.9;
    const SensorFitResult f = fitSensor(r.log, r.sat, groups, urg04lx(), &bocas().calib, cfg);
    for (size_t g = 0; g < groups.size(); ++g) {
        const RangeFit& rf = f.ranges[g];
        ASSERT_TRUE(rf.fitted) << rf.group << ": " << rf.diagnosis;
        if (rf.group == "target_gold") {
            EXPECT_NEAR(rf.bias_slope.value, k_m, 4 * rf.bias_slope.se + 0.05 * k_m);
            EXPECT_GT(rf.bias_slope.value / rf.bias_slope.se, 10);
        } else {
            EXPECT_LT(std::abs(rf.bias_slope.value), 4 * rf.bias_slope.se + 0.01) << rf.group;
        }
        // The datasheet noise (5 mm below 1 m, 0.5 % beyond: 12.5 mm at 2.5 m) in clear air.
        EXPECT_NEAR(rf.noise0.value, 0.0125, 0.002) << rf.group;
    }
}

// The bootstrap's replicates run on every core; each draws from its own key, so the errors are
// the same doubles on one thread as on all of them.
TEST(SensorFit, TheBootstrapsErrorsAreTheSameOnOneThreadAsOnAll)
{
    const auto groups = targetGroups();
    const SimRun r = simulate(3, 0.007, 7.3, 0.01);
    SensorFitConfig cfg;
    cfg.bootstrap = 12;
    auto fitWith = [&](size_t threads) {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, threads);
        return fitSensor(r.log, r.sat, groups, urg04lx(), &bocas().calib, cfg);
    };
    const SensorFitResult one = fitWith(1), all = fitWith(std::max<size_t>(2, std::thread::hardware_concurrency()));
    ASSERT_TRUE(one.ok());
    ASSERT_EQ(one.bootstrap_replicates, 12);
    EXPECT_EQ(one.offset.offset_s.value, all.offset.offset_s.value);
    EXPECT_EQ(one.offset.offset_s.se, all.offset.offset_s.se);
    EXPECT_GE(one.offset.bootstrap_fits, 10);
    // The offset's error is the replicates' spread, not the search grid's floor it may not go below.
    EXPECT_GT(one.offset.offset_s.se, cfg.offset_step_s / std::sqrt(12.0));
    for (size_t g = 0; g < groups.size(); ++g) {
        if (one.thresholds[g].fitted) EXPECT_GE(one.thresholds[g].bootstrap_fits, 10) << groups[g].name;
        EXPECT_EQ(one.thresholds[g].S_star.value, all.thresholds[g].S_star.value) << groups[g].name;
        EXPECT_EQ(one.thresholds[g].S_star.se, all.thresholds[g].S_star.se) << groups[g].name;
    }
}

TEST(SensorFit, DegenerateRunsAreDiagnosedNotFitted)
{
    const auto groups = targetGroups();
    auto has = [](const SensorFitResult& f, const std::string& needle) {
        for (const auto& d : f.diagnoses)
            if (d.find(needle) != std::string::npos) return true;
        return false;
    };
    {  // Only the first, short machine run: the smoke never reaches the threshold.
        const SimRun r = simulate(1, 0.007, 0, 0.01, 0, 80);
        const auto f = fitSensor(r.log, r.sat, groups, urg04lx(), &bocas().calib);
        EXPECT_FALSE(f.ok());
        EXPECT_TRUE(has(f, "no smoke event"));
        for (const auto& th : f.thresholds) EXPECT_NE(th.diagnosis.find("no error codes"), std::string::npos);
    }
    {  // Inside the thick smoke only: every beam an error.
        const SimRun r = simulate(1, 0.007, 0, 0.01, 110, 250);
        const auto f = fitSensor(r.log, r.sat, groups, urg04lx(), &bocas().calib);
        EXPECT_FALSE(f.ok());
        EXPECT_TRUE(has(f, "all-error"));
    }
    {  // The run stops before the smoke clears: one crossing, the offset cannot be told apart.
        const SimRun r = simulate(1, 0.007, 0.0, 0.01, 0, 200);
        const auto f = fitSensor(r.log, r.sat, groups, urg04lx(), &bocas().calib);
        EXPECT_TRUE(has(f, "never return"));
        EXPECT_FALSE(f.offset.estimated);
        ASSERT_TRUE(f.ok());  // the threshold still follows, with the offset held at the given one
        EXPECT_NEAR(f.thresholds[1].S_star.value, trueThreshold(groups[1], 0.007), 3.5 * f.thresholds[1].S_star.se);
        // A diagnosed run keeps the floor's errors: the bootstrap would draw from a model the data
        // do not pin (here, the clock offset).
        EXPECT_NE(f.error_method.find("analytic floor"), std::string::npos) << f.error_method;
        EXPECT_EQ(f.thresholds[1].bootstrap_fits, 0);
        // Between one and nine replicates cannot give a spread: refused.
        SensorFitConfig few;
        few.bootstrap = 5;
        EXPECT_THROW(fitSensor(r.log, r.sat, groups, urg04lx(), &bocas().calib, few), Error);
    }
    {  // A saturation series that never changes: nothing to read a threshold off.
        SimRun r = simulate(1, 0.007, 0, 0.01, 0, 360);
        for (double& S : r.sat.saturation) S = 0.5;
        const auto f = fitSensor(r.log, r.sat, groups, urg04lx(), &bocas().calib);
        EXPECT_FALSE(f.ok());
        EXPECT_TRUE(has(f, "never changes"));
    }
    {  // The camera's clock is 1000 s off: nothing overlaps within the search window.
        const SimRun r = simulate(1, 0.007, 1000.0, 0.01, 0, 360);
        const auto f = fitSensor(r.log, r.sat, groups, urg04lx(), &bocas().calib);
        EXPECT_FALSE(f.ok());
        EXPECT_TRUE(has(f, "do not overlap"));
    }
}

namespace {
/// The built-in plume scene's Sick (physical model) at 0.25 Hz, its noise floor scaled by `nf_scale`.
RecordedLog sickInPlumes(double nf_scale, uint64_t seed)
{
    static const Scene plume = loadScene("plume");
    static const SurfaceSet surfaces(plume);
    Scene scene = plume;
    const size_t si = size_t(scene.findSensor("lms200"));
    scene.sensors[si].config.physical.noise_floor *= nf_scale;
    ScanConfig sc;
    sc.sensor = scene.sensors[si].name;
    sc.model = SensorModel::Physical;
    sc.rate_hz = 0.25;
    sc.seed = seed;
    sc.keep_beams = false;
    const Scanner scanner(scene, surfaces, sc);
    return logOf(scanner);
}
}  // namespace

// The Sick in plumes: the depth it reads into a plume falls as the plume thickens (k > 0); a
// depth bias planted in the log is found.
TEST(PlumeFit, SickPenetrationFallsWithDensityAndFindsAPlantedDepthBias)
{
    const Scene scene = loadScene("plume");
    const SurfaceSet surfaces(scene);
    const SensorMount& mount = scene.sensors[size_t(scene.findSensor("lms200"))];
    const PlumeFitResult a = fitSickPlume(sickInPlumes(1.0, 3), scene, surfaces, mount);
    ASSERT_TRUE(a.ok) << (a.diagnoses.empty() ? "" : a.diagnoses.front());
    EXPECT_GT(a.exponent.value, 5 * a.exponent.se) << a.exponent.value;
    EXPECT_GT(a.depth_m.value, 0.0);
    // The densest bin with echoes reads shallower than the deepest-reading bin with a fair number
    // of them. (Not the thinnest: with smoke's backscatter, thin plumes echo from their first dense
    // patch and read shallow too, and which thin bin first holds 20 echoes depends on the plumes'
    // rasterisation, which differs between compilers in the last bits.)
    const PlumeFitResult::Bin* deep = nullptr;
    const PlumeFitResult::Bin* dense = nullptr;
    for (const auto& b : a.bins)
        if (b.echo >= 20) {
            if (!deep || b.mean_depth_m > deep->mean_depth_m) deep = &b;
            dense = &b;
        }
    ASSERT_TRUE(deep && dense && deep != dense);
    for (const auto& b : a.bins)
        std::printf("bin %.3g-%.3g: %d echoes, depth %.3f +- %.3f m\n", b.rho_lo, b.rho_hi, b.echo, b.mean_depth_m,
                    b.se_depth_m);
    EXPECT_LT(dense->mean_depth_m + 3 * dense->se_depth_m, deep->mean_depth_m - 3 * deep->se_depth_m);
    // The share of beams that echo from the plume grows with its density (thin smoke is seen
    // through or gives errors, cores read as obstacles); the maximum-likelihood logistic follows
    // every well-filled bin within its binomial error (inflated by the bins' over-dispersion).
    ASSERT_TRUE(std::isfinite(a.rho_50.value) && a.rho_50.se > 0);
    EXPECT_GT(a.slope.value, 3 * a.slope.se);
    const double inflation = std::max(1.0, a.share_chi2 / a.share_dof);
    for (const auto& bin : a.bins) {
        if (bin.n < 30) continue;
        const double x = 0.5 * (std::log(bin.rho_lo) + std::log(bin.rho_hi));
        const double p = 1 / (1 + std::exp(-a.slope.value * (x - std::log(a.rho_50.value))));
        EXPECT_NEAR(double(bin.echo) / bin.n, p, 4 * std::sqrt(inflation * p * (1 - p) / bin.n) + 1e-3)
            << "bin " << bin.rho_lo << "-" << bin.rho_hi << " n " << bin.n;
    }
    // Planted in the data: every smoke echo read 0.1 m long (a later trigger in smoke). The fitted
    // depth at the same density grows by about that, beyond both errors; the surfaces are untouched.
    RecordedLog planted = sickInPlumes(1.0, 3);
    for (auto& sc : planted.scans)
        for (size_t i = 0; i < sc.range.size(); ++i) {
            const Ray ray = mount.beamRay(sc.angle_rad[i]);
            const SurfaceHit h = surfaces.closest(ray, 8.0);
            const double surface_mm = 1000 * (h.hit ? h.t_m : 8.0);
            if (sc.range[i] < 8183 && sc.range[i] < surface_mm - 50) sc.range[i] += 100;
        }
    const PlumeFitResult b = fitSickPlume(planted, scene, surfaces, mount);
    ASSERT_TRUE(b.ok);
    const Estimate da = plumeDepthAt(a, a.rho_ref), db = plumeDepthAt(b, a.rho_ref);
    EXPECT_NEAR(da.value, a.depth_m.value, 1e-12);
    EXPECT_GT(db.value - da.value, 3 * std::hypot(da.se, db.se))
        << da.value << " +- " << da.se << " vs " << db.value << " +- " << db.se;
    EXPECT_LT(db.value - da.value, 0.2);
    // Bad set-ups are errors, not fits: a URG in the plume fit, a scene without plumes.
    const Scene bocas = loadScene("bocas");
    EXPECT_THROW(
        fitSickPlume(RecordedLog{}, bocas, SurfaceSet(bocas), bocas.sensors[size_t(bocas.findSensor("lms200"))]),
        Error);
    EXPECT_THROW(fitSickPlume(RecordedLog{}, scene, surfaces, SensorMount{}), Error);
}
