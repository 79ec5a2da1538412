// fitSensor: recorded laser log + saturation series → clock offset, thresholds, penetration power,
// range bias/noise, with a diagnosis wherever the data cannot support a fit.
#include "smokescan/fit/sensor_fit.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "fit_bootstrap.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/core/order_stats.hpp"
#include "threshold_fit.hpp"

namespace smokescan {

RangeFit fitRangeBiasNoise(const std::string& group, const std::vector<std::vector<double>>& range_m,
                           const std::vector<double>& S, double S_clear_min,
                           const SensorFitConfig& cfg);  // range_fit.cpp

namespace {

/// Replicates that must fit for the bootstrap's spread to replace the floor.
constexpr int kMinBootstrapFits = 10;
/// The offset grid's size on each side of its centre (--offset-window / --offset-step): 1 h at 0.1 s.
constexpr int kMaxOffsetSteps = 36000;

/// Per group: the beams of the log it holds, and per scan the errors and valid ranges.
struct GroupData {
    std::vector<int> beams;
    detail::GroupCounts counts;  ///< all scans
    std::vector<std::vector<double>> range_m;  ///< [scan][beam in group], NaN = error
};

/// Fraction of beams classified right by the best split of saturation, uncovered scans counting
/// one half (so a δ that pushes scans out of the camera's span gains nothing).
double agreement(const std::vector<GroupData>& gd, const SaturationSeries& sat, double delta,
                 std::vector<double>* split)
{
    double correct = 0, total = 0;
    std::vector<std::pair<double, size_t>> order;
    for (size_t g = 0; g < gd.size(); ++g) {
        const auto& c = gd[g].counts;
        order.clear();
        for (size_t k = 0; k < c.t.size(); ++k) {
            total += c.n[k];
            const double S = saturationAt(sat, c.t[k] + delta);
            if (std::isnan(S))
                correct += 0.5 * c.n[k];
            else
                order.emplace_back(S, k);
        }
        std::sort(order.begin(), order.end());
        // Split after position i: scans below are predicted error, above clear.
        double clean_above = 0;
        for (const auto& [S, k] : order) clean_above += c.n[k] - c.e[k];
        double best = clean_above, err_below = 0, best_S = order.empty() ? NAN : order.front().first;
        for (size_t i = 0; i < order.size(); ++i) {
            const size_t k = order[i].second;
            err_below += c.e[k];
            clean_above -= c.n[k] - c.e[k];
            if (err_below + clean_above > best) {
                best = err_below + clean_above;
                best_S = i + 1 < order.size() ? 0.5 * (order[i].first + order[i + 1].first) : order[i].first;
            }
        }
        correct += best;
        if (split) (*split)[g] = best_S;
    }
    return total > 0 ? correct / total : 0;
}

/// Onsets and recoveries of the majority error state: the time midway between the last scan before
/// and the first scan after each change, counting a state only once it has lasted `hold_s`.
std::vector<double> transitionTimes(const std::vector<GroupData>& gd, size_t n_scans, double hold_s)
{
    std::vector<double> out;
    int state = -1, cand = -1;
    double cand_since = 0, prev_t = 0, change_mid = 0;
    for (size_t k = 0; k < n_scans; ++k) {
        long long e = 0, n = 0;
        double t = 0;
        for (const auto& g : gd) {
            e += g.counts.e[k];
            n += g.counts.n[k];
            t = g.counts.t[k];
        }
        const int s = 2 * e > n;
        if (s != cand) {
            cand = s;
            cand_since = t;
            change_mid = k ? 0.5 * (prev_t + t) : t;
        }
        if (cand != state && t - cand_since >= hold_s) {
            if (state >= 0) out.push_back(change_mid);
            state = cand;
        }
        prev_t = t;
    }
    return out;
}

}  // namespace

double saturationAt(const SaturationSeries& s, double t)
{
    if (s.time_s.empty() || t < s.time_s.front() || t > s.time_s.back()) return NAN;
    return detail::interpolate(s, t);
}

SaturationSeries movingAverage(const SaturationSeries& s, int h)
{
    h = std::max(h, 0);
    SaturationSeries out = s;
    const int n = int(s.time_s.size());
    for (int i = 0; i < n; ++i) {
        const int r = std::min({h, i, n - 1 - i});
        double sum = 0;
        for (int j = i - r; j <= i + r; ++j) sum += s.saturation[size_t(j)];
        out.saturation[size_t(i)] = sum / (2 * r + 1);
    }
    return out;
}

double saturationNoise(const SaturationSeries& s) { return detail::noiseOfSeries(s.saturation); }

const char* errorLinkName(ErrorLink link) { return link == ErrorLink::Logistic ? "logistic" : "probit"; }

namespace {

/// One run of fitSensor: its inputs, the state its stages share, and the result they fill.
/// Each stage is one step of docs/fitting.md, in order.
class SensorFit {
public:
    SensorFit(const RecordedLog& log, const std::vector<BeamGroup>& groups, const LrfSpec& spec,
              const CurveFitResult* calibration, const SensorFitConfig& cfg, const FailureMask& failed)
        : log_(log),
          groups_(groups),
          spec_(spec),
          failed_(failed),
          calibration_(calibration),
          cfg_(cfg),
          K_(log.scans.size())
    {
        res_.groups = groups;
    }

    SensorFitResult run(const SaturationSeries& raw)
    {
        raw_ = &raw;
        smoothSaturation(raw);
        collectGroups();
        summariseGroups();
        if (!spansMeet()) return res_;
        if (!findFittableGroups()) return res_;
        startOffset();
        fitThresholds();
        floorErrors();
        bootstrapErrors();
        penetrationAndRanges();
        chooseReference();
        alignStreams();
        return res_;
    }

private:
    const RecordedLog& log_;
    const std::vector<BeamGroup>& groups_;
    const LrfSpec& spec_;
    const FailureMask& failed_;
    const CurveFitResult* calibration_;
    SensorFitConfig cfg_;  ///< a copy: the bootstrap's replicates narrow the offset search
    const SaturationSeries* raw_ = nullptr;  ///< the measured saturation, for the bootstrap
    const size_t K_;
    SensorFitResult res_;
    SaturationSeries sat_;  ///< the saturation, smoothed over 2h + 1 frames
    int h_ = 0;
    double frame_s_ = 0, S_min_ = 0, S_max_ = 0;
    std::vector<GroupData> gd_;  ///< per group: beams, counts, ranges
    std::vector<size_t> usable_;  ///< groups with enough beams
    std::vector<size_t> fit_groups_;  ///< usable groups with both errors and clear readings
    std::vector<double> trans_;  ///< onset and recovery times [s]
    std::vector<double> split_;  ///< per fit group: the best-splitting saturation
    bool fit_offset_ = false;
    double delta0_ = 0;  ///< the offset the thresholds start from [s]
    double sigma_S_ = 0;  ///< the smoothed saturation's noise
    std::vector<double> S_at_;  ///< saturation at each scan (offset applied)
    std::vector<double> gap_se_;  ///< per group: a sharp step's resolution, its gap/√12 (else 0)

    /// The saturation, smoothed: its noise σ_S shrinks by √(2h + 1) and enters the width.
    void smoothSaturation(const SaturationSeries& raw)
    {
        std::vector<double> dt;
        for (size_t i = 1; i < raw.time_s.size(); ++i) dt.push_back(raw.time_s[i] - raw.time_s[i - 1]);
        frame_s_ = std::max(quantile(dt, 0.5), 1e-6);
        const double span_s = raw.time_s.empty() ? 0.0 : raw.time_s.back() - raw.time_s.front();
        if (cfg_.smooth_s > span_s)
            throw Error("--smooth",
                        "a window of " + fmt("%g", cfg_.smooth_s) + " s is longer than the saturation series (" +
                            fmt("%g", span_s) + " s)");
        h_ = int(std::min(std::floor(0.5 * cfg_.smooth_s / frame_s_ + 1e-9), double(raw.time_s.size())));
        sat_ = movingAverage(raw, h_);
        res_.saturation_noise = detail::noiseOfSeries(raw.saturation);
        res_.smoothing_samples = 2 * h_ + 1;
    }

    /// Which beams each group holds (by the first scan's angles), and what each scan saw on them.
    void collectGroups()
    {
        gd_.resize(groups_.size());
        const auto& a0 = log_.scans.front().angle_rad;
        for (size_t g = 0; g < groups_.size(); ++g)
            for (size_t i = 0; i < a0.size(); ++i)
                if (groups_[g].contains(a0[i])) gd_[g].beams.push_back(int(i));
        for (auto& d : gd_)
            for (size_t k = 0; k < K_; ++k) {
                const LaserLogScan& s = log_.scans[k];
                int e = 0;
                std::vector<double> r;
                for (int i : d.beams) {
                    const double m = s.range[size_t(i)] * log_.unit_m;
                    const bool err = failed_.empty() ? spec_.isErrorRange(m) : bool(failed_[k][size_t(i)]);
                    e += err;
                    r.push_back(err ? NAN : m);
                }
                d.counts.t.push_back(s.time_s);
                d.counts.n.push_back(int(d.beams.size()));
                d.counts.e.push_back(e);
                d.range_m.push_back(std::move(r));
            }
    }

    /// Each group's beams, scans and errors; groups with too few beams are left out.
    void summariseGroups()
    {
        res_.thresholds.resize(groups_.size());
        res_.ranges.resize(groups_.size());
        for (size_t g = 0; g < groups_.size(); ++g) {
            auto& th = res_.thresholds[g];
            th.group = res_.ranges[g].group = groups_[g].name;
            th.beams = int(gd_[g].beams.size());
            th.scans = int(K_);
            for (size_t k = 0; k < K_; ++k) {
                th.errors += gd_[g].counts.e[k];
                th.observations += gd_[g].counts.n[k];
            }
            if (th.beams < cfg_.min_beams)
                th.diagnosis = "only " + std::to_string(th.beams) + " beams of the log fall in its angles";
            else
                usable_.push_back(g);
        }
    }

    /// Do the clocks' spans meet for some offset in the window?
    bool spansMeet()
    {
        const double t0 = log_.scans.front().time_s, t1 = log_.scans.back().time_s;
        const double c0 = sat_.time_s.front(), c1 = sat_.time_s.back();
        const double lo = cfg_.estimate_offset ? cfg_.offset_s - cfg_.offset_window_s : cfg_.offset_s;
        const double hi = cfg_.estimate_offset ? cfg_.offset_s + cfg_.offset_window_s : cfg_.offset_s;
        if (t1 + hi >= c0 && t0 + lo <= c1) return true;
        res_.diagnoses.push_back(
            fmt("time spans do not overlap: laser %.1f-%.1f s, camera %.1f-%.1f s", t0, t1, c0, c1) +
            (cfg_.estimate_offset ? fmt(" for any offset within %.1f +/- %.1f s", cfg_.offset_s, cfg_.offset_window_s)
                                  : fmt(" at offset %.1f s", cfg_.offset_s)) +
            "; give --offset (camera time - laser time)");
        return false;
    }

    /// Degenerate groups (never an error, or nothing but errors) are diagnosed; true when some
    /// group is left to fit.
    bool findFittableGroups()
    {
        S_min_ = *std::min_element(sat_.saturation.begin(), sat_.saturation.end());
        S_max_ = *std::max_element(sat_.saturation.begin(), sat_.saturation.end());
        if (S_max_ - S_min_ < 1e-9) {
            res_.diagnoses.push_back(
                fmt("the saturation never changes (%.4f throughout): no threshold can be read off it", S_min_));
            return false;
        }
        for (size_t g : usable_) {
            auto& th = res_.thresholds[g];
            if (th.errors == 0)
                th.diagnosis =
                    fmt("no error codes: the threshold lies below the lowest saturation seen (%.3f)", S_min_);
            else if (th.errors == th.observations)
                th.diagnosis = fmt(
                    "every beam returned an error code: the threshold lies above the highest saturation seen (%.3f)",
                    S_max_);
            else
                fit_groups_.push_back(g);
        }
        long long errs = 0, obs = 0;
        for (size_t g : usable_) {
            errs += res_.thresholds[g].errors;
            obs += res_.thresholds[g].observations;
        }
        if (usable_.empty())
            res_.diagnoses.push_back("no beam group has enough beams in the log");
        else if (errs == 0)
            res_.diagnoses.push_back(
                "no smoke event: no beam of any group returned an error code, so no threshold can be fitted");
        else if (errs == obs)
            res_.diagnoses.push_back("all-error log: every beam returned an error code, so no threshold can be fitted");
        return !fit_groups_.empty();
    }

    /// The fit groups' data, in fit order.
    std::vector<GroupData> fitGroupData() const
    {
        std::vector<GroupData> fg;
        for (size_t g : fit_groups_) fg.push_back(gd_[g]);
        return fg;
    }

    /// The clock offset's start: onsets and recoveries pin it; one transition alone cannot. A
    /// grid search of the agreement between error states and a saturation split.
    void startOffset()
    {
        const std::vector<GroupData> fg = fitGroupData();
        const double hold = std::max(1.0, 3 * spec_.scan_period_s);
        trans_ = transitionTimes(fg, K_, hold);
        res_.offset.transitions = int(trans_.size());
        const double first_t = trans_.empty() ? NAN : trans_.front();
        fit_offset_ = cfg_.estimate_offset;
        if (fit_offset_ && res_.offset.transitions < 2) {
            fit_offset_ = false;
            res_.offset.diagnosis = res_.offset.transitions == 1
                ? fmt("errors change state once only (at %.1f s) and never return: one crossing cannot tell the clock offset from the "
                      "threshold, so the offset is held at %.2f s (give --offset)",
                      first_t, cfg_.offset_s)
                : fmt("the error state never settles into an onset and a recovery: the offset is held at %.2f s (give --offset)",
                      cfg_.offset_s);
            res_.diagnoses.push_back(res_.offset.diagnosis);
        }
        split_.assign(fg.size(), NAN);
        delta0_ = cfg_.offset_s;
        if (fit_offset_)
            searchOffset(fg);
        else
            res_.offset.offset_s = {cfg_.offset_s, 0.0};
        agreement(fg, sat_, delta0_, &split_);
    }

    /// The offset grid: the plateau of best agreement, its centre and width.
    void searchOffset(const std::vector<GroupData>& fg)
    {
        const int steps = int(std::ceil(cfg_.offset_window_s / cfg_.offset_step_s));
        double best = -1;
        int best_i = 0, best_j = 0;  // plateau of the maximum
        for (int i = -steps; i <= steps; ++i) {
            if (cfg_.stop && *cfg_.stop) throw Error("fit", "stopped");
            const double d = cfg_.offset_s + i * cfg_.offset_step_s, a = agreement(fg, sat_, d, nullptr);
            res_.offset.agreement.emplace_back(d, a);
            if (a > best + 1e-12) {
                best = a;
                best_i = best_j = i;
            } else if (a > best - 1e-12 && best_j == i - 1)
                best_j = i;
        }
        delta0_ = cfg_.offset_s + 0.5 * (best_i + best_j) * cfg_.offset_step_s;
        res_.offset.offset_s = {delta0_, (best_j - best_i + 1) * cfg_.offset_step_s / std::sqrt(12.0)};
        res_.offset.estimated = true;  // refined below unless every group's step is sharp
        if (best_i == -steps || best_j == steps)
            res_.diagnoses.push_back(
                fmt("the best clock offset lies at the edge of the search (%.1f s): widen --offset-window", delta0_));
    }

    /// Sharp steps (errors and clear scans separate) have no width to fit: S* lies in the gap.
    /// The others go to the joint likelihood fit (threshold_fit.hpp).
    void fitThresholds()
    {
        detail::ThresholdProblem prob;
        prob.sat = &sat_;
        prob.logistic = cfg_.link == ErrorLink::Logistic;
        prob.fit_offset = fit_offset_;
        prob.offset0 = delta0_;
        prob.cluster_s = std::max({(2 * h_ + 2) * frame_s_, 2 * spec_.scan_period_s, 1e-3});
        prob.sigma_S = sigma_S_ = res_.saturation_noise / std::sqrt(2.0 * h_ + 1);
        gap_se_.assign(groups_.size(), 0.0);
        std::vector<size_t> smooth;
        for (size_t j = 0; j < fit_groups_.size(); ++j) {
            const size_t g = fit_groups_[j];
            detail::GroupCounts c;
            double err_max = -1, clean_min = 2;
            for (size_t k = 0; k < K_; ++k) {
                const double S = saturationAt(sat_, gd_[g].counts.t[k] + delta0_);
                if (std::isnan(S)) continue;
                c.t.push_back(gd_[g].counts.t[k]);
                c.n.push_back(gd_[g].counts.n[k]);
                c.e.push_back(gd_[g].counts.e[k]);
                if (c.e.back() > 0) err_max = std::max(err_max, S);
                if (c.e.back() < c.n.back()) clean_min = std::min(clean_min, S);
            }
            auto& th = res_.thresholds[g];
            th.dof = std::max(0, int(c.t.size()) - 2);
            if (err_max < 0 || clean_min > 1) {
                th.diagnosis = "within the camera's span the beams are all clear or all errors";
                continue;
            }
            if (err_max < clean_min) {
                th.fitted = th.sharp = true;
                th.S_star = {0.5 * (err_max + clean_min), (clean_min - err_max) / std::sqrt(12.0)};
                gap_se_[g] = th.S_star.se;
                th.width = {0.0, NAN};
                th.diagnosis = fmt(
                    "sharp step: every scan below saturation %.4f had errors, none above %.4f; the width is below the "
                    "saturation's resolution",
                    err_max, clean_min);
                continue;
            }
            prob.groups.push_back(std::move(c));
            prob.start.push_back({std::isfinite(split_[j]) ? split_[j] : 0.5 * (err_max + clean_min),
                                  std::max(0.01, 0.05 * (S_max_ - S_min_))});
            smooth.push_back(g);
        }
        if (!smooth.empty()) takeSolution(detail::solveThresholds(prob), smooth);
    }

    /// The likelihood fit's thresholds and offset into the result.
    void takeSolution(const detail::ThresholdSolution& sol, const std::vector<size_t>& smooth)
    {
        if (fit_offset_)
            res_.offset = {true,
                           {sol.offset, sol.offset_se},
                           res_.offset.transitions,
                           res_.offset.agreement,
                           res_.offset.diagnosis};
        for (size_t j = 0; j < smooth.size(); ++j) {
            auto& th = res_.thresholds[smooth[j]];
            th.fitted = sol.converged;
            if (!sol.converged) th.diagnosis = "the fit did not converge: " + sol.message;
            th.S_star = {sol.sw[j][0], std::sqrt(sol.cov[j](0, 0))};
            th.width = {sol.sw[j][1], std::sqrt(sol.cov[j](1, 1))};
            th.cov_S_star_width = sol.cov[j](0, 1);
            th.pearson_chi2 = sol.pearson_chi2[j];
            th.deviance = sol.deviance[j];
            th.variance_inflation = sol.inflation[j];
            th.dof = std::max(0, sol.nobs[j] - 2);
            if (sigma_S_ == 0 && th.width.value <= 2 * detail::kMinWidth) {
                th.sharp = true;
                th.diagnosis = "the width reached its floor: the step is sharper than the data resolve";
            }
        }
    }

    /// What the data can say at most, whatever the likelihood's curvature claims: each onset or
    /// recovery is timed only to the scan interval (uniform, Δt/√12) and read on a saturation of
    /// noise σ_S; with slope dS/dt at the crossing, it fixes S* to √(σ_S² + (Ṡ·Δt)²/12) and the
    /// offset to that over |Ṡ|. Combined over transitions, these floor the reported errors.
    void floorErrors()
    {
        const double delta = res_.offset.offset_s.value;
        const double dt_scan =
            K_ > 1 ? (log_.scans.back().time_s - log_.scans.front().time_s) / double(K_ - 1) : spec_.scan_period_s;
        const double half = std::max(1.0, 0.5 * cfg_.smooth_s);
        double info_S = 0, info_t = 0;
        for (double t : trans_) {
            const double a = saturationAt(sat_, t + delta - half), b = saturationAt(sat_, t + delta + half);
            if (std::isnan(a) || std::isnan(b)) continue;
            const double slope = (b - a) / (2 * half);
            const double var_S = sigma_S_ * sigma_S_ + slope * slope * dt_scan * dt_scan / 12;
            info_S += 1 / var_S;
            if (slope != 0) info_t += slope * slope / var_S;
        }
        if (info_t > 0 && res_.offset.estimated)
            res_.offset.offset_s.se = std::max(res_.offset.offset_s.se, std::sqrt(1 / info_t));
        if (info_S > 0)
            for (size_t g : fit_groups_) {
                auto& th = res_.thresholds[g];
                if (th.fitted) th.S_star.se = std::max(th.S_star.se, std::sqrt(1 / info_S));
            }
    }

    /// The errors on S* and the offset from a parametric bootstrap (cfg_.bootstrap replicates): the
    /// spread of the refits of streams drawn from the fitted model. Where fewer than ten replicates
    /// fit, the floor's errors stay.
    void bootstrapErrors()
    {
        const bool any_fitted =
            std::any_of(fit_groups_.begin(), fit_groups_.end(), [&](size_t g) { return res_.thresholds[g].fitted; });
        if (!any_fitted) return;
        res_.error_method = "the analytic floor (--bootstrap 0)";
        if (cfg_.bootstrap <= 0) return;
        // The bootstrap draws from a model the data support; a run the fit already diagnosed (one
        // crossing, the offset at the search's edge, ...) keeps the floor's errors.
        if (!res_.diagnoses.empty()) {
            res_.error_method = "the analytic floor: the bootstrap needs a run without the diagnoses above";
            return;
        }
        // The truth at each scan, the same for every group and replicate.
        std::vector<double> S_truth;
        for (const LaserLogScan& scan : log_.scans)
            S_truth.push_back(saturationAt(sat_, scan.time_s + res_.offset.offset_s.value));
        std::vector<detail::GroupModel> models;
        std::vector<const std::vector<int>*> counts;
        for (size_t g : fit_groups_) {
            models.push_back(groupModel(g, S_truth));
            counts.push_back(&gd_[g].counts.e);
        }
        // The replicates search the offset near the fit's: far wider than its floor's error.
        const double window =
            std::min(cfg_.offset_window_s, std::max(2.5, 8 * res_.offset.offset_s.se + 2 * cfg_.offset_step_s));
        const uint64_t key = detail::dataKey(raw_->saturation, counts);
        // The replicates on every core: each draws from its own key, so the same whatever the
        // thread count.
        std::vector<std::vector<double>> reps(size_t(cfg_.bootstrap));  // offset, then each fit group's S*
        tbb::parallel_for(0, cfg_.bootstrap, [&](int b) {
            if (cfg_.stop && *cfg_.stop) throw Error("fit", "stopped");
            reps[size_t(b)] = replicate(key, uint64_t(b), models, S_truth, window);
        });
        auto column = [&](size_t j, int* fits) {
            std::vector<double> v;
            for (const auto& r : reps) v.push_back(r[j]);
            *fits = int(std::count_if(v.begin(), v.end(), [](double x) { return std::isfinite(x); }));
            return detail::finiteSpread(v, kMinBootstrapFits);
        };
        res_.bootstrap_replicates = cfg_.bootstrap;
        int fits = 0;
        const double se_offset = column(0, &fits);
        if (fit_offset_ && std::isfinite(se_offset)) {
            // Never below the search grid's resolution.
            res_.offset.offset_s.se = std::max(se_offset, cfg_.offset_step_s / std::sqrt(12.0));
            res_.offset.bootstrap_fits = fits;
        }
        std::string floored = fit_offset_ && res_.offset.bootstrap_fits == 0 ? "the offset" : "";
        for (size_t j = 0; j < fit_groups_.size(); ++j) {
            auto& th = res_.thresholds[fit_groups_[j]];
            const double se = column(j + 1, &fits);
            if (!th.fitted) continue;
            if (!std::isfinite(se)) {
                floored += (floored.empty() ? "" : ", ") + th.group;
                continue;
            }
            th.S_star.se = std::max(se, gap_se_[fit_groups_[j]]);  // never below a sharp step's gap
            th.bootstrap_fits = fits;
        }
        res_.error_method = fmt("parametric bootstrap, %d replicates", cfg_.bootstrap) +
            (floored.empty() ? std::string()
                             : "; the analytic floor for " + floored + " (fewer than 10 replicates fitted)");
    }

    /// A fit group's model as the bootstrap draws from it; S_truth: the smoothed saturation at each scan.
    detail::GroupModel groupModel(size_t g, const std::vector<double>& S_truth) const
    {
        const ThresholdFit& th = res_.thresholds[g];
        detail::GroupModel m;
        m.S_star = th.S_star.value;
        // A width well below the smoothed saturation's noise is not resolved: a step.
        m.width = th.sharp || !(th.width.value > 0.5 * sigma_S_) ? 0.0 : th.width.value;
        m.logistic = cfg_.link == ErrorLink::Logistic;
        if (m.width == 0) {
            std::vector<std::vector<bool>> failed;
            for (size_t k = 0; k < K_; ++k) {
                std::vector<bool> f;
                for (double r : gd_[g].range_m[k]) f.push_back(std::isnan(r));
                failed.push_back(std::move(f));
            }
            m.beam_offset = detail::beamThresholdSpread(failed, S_truth);
        }
        return m;
    }

    /// One replicate: the smoothed saturation is the truth; the camera's frames get fresh white
    /// noise of the measured level, each group's errors are drawn from its model at the truth, and
    /// the offset and thresholds are fitted again (the offset within `window` of the fit's).
    /// Returns the offset, then each fit group's S* (NaN where it did not fit).
    std::vector<double> replicate(uint64_t key, uint64_t b, const std::vector<detail::GroupModel>& models,
                                  const std::vector<double>& S_truth, double window) const
    {
        SensorFit r(*this);
        KeyedRng rng(key, b);
        SaturationSeries raw = *raw_;
        for (size_t i = 0; i < raw.time_s.size(); ++i)
            raw.saturation[i] = sat_.saturation[i] + res_.saturation_noise * rng.normal();
        r.sat_ = movingAverage(raw, h_);
        r.res_.saturation_noise = detail::noiseOfSeries(raw.saturation);
        const double delta = res_.offset.offset_s.value;
        for (size_t j = 0; j < fit_groups_.size(); ++j)
            detail::drawErrorCounts(models[j], S_truth, rng, r.gd_[fit_groups_[j]].counts);
        r.res_.offset = {};
        r.res_.diagnoses.clear();
        for (auto& th : r.res_.thresholds) th = ThresholdFit{};
        r.cfg_.offset_s = delta;
        r.cfg_.offset_window_s = window;
        r.cfg_.estimate_offset = fit_offset_;
        r.startOffset();
        // A replicate whose offset is held where the fit's was free (too few transitions) would
        // narrow both spreads: it does not count.
        if (r.fit_offset_ != fit_offset_) return std::vector<double>(fit_groups_.size() + 1, NAN);
        r.fitThresholds();
        std::vector<double> out{r.res_.offset.offset_s.value};
        for (size_t g : fit_groups_)
            out.push_back(r.res_.thresholds[g].fitted ? r.res_.thresholds[g].S_star.value : NAN);
        return out;
    }

    /// Penetration power and optical depth through the calibration curve; range bias and noise.
    void penetrationAndRanges()
    {
        const double delta = res_.offset.offset_s.value;
        S_at_.resize(K_);
        for (size_t k = 0; k < K_; ++k) S_at_[k] = saturationAt(sat_, log_.scans[k].time_s + delta);
        std::vector<double> seen;
        for (double s : S_at_)
            if (!std::isnan(s)) seen.push_back(s);
        const double S_clear = quantile(seen, cfg_.clear_quantile);
        for (size_t g : usable_) {
            auto& th = res_.thresholds[g];
            th.range_m = groups_[g].range_m > 0 ? groups_[g].range_m : clearAirRange(g, S_clear);
            if (th.fitted && calibration_) throughCalibration(th);
            double S_clear_min = S_clear;
            if (th.fitted && !th.sharp) S_clear_min = std::max(S_clear, th.S_star.value + 3 * th.width.value);
            res_.ranges[g] = fitRangeBiasNoise(groups_[g].name, gd_[g].range_m, S_at_, S_clear_min, cfg_);
        }
    }

    /// Laser–surface distance when the group does not give it: the median valid range in clear air.
    double clearAirRange(size_t g, double S_clear) const
    {
        std::vector<double> r;
        for (size_t k = 0; k < K_; ++k)
            if (S_at_[k] >= S_clear)
                for (double m : gd_[g].range_m[k])
                    if (!std::isnan(m)) r.push_back(m);
        return quantile(r, 0.5);
    }

    /// S* as a density, a penetration power and an optical depth.
    void throughCalibration(ThresholdFit& th) const
    {
        try {
            const auto [rho, se] = calibration_->invert(th.S_star.value, th.S_star.se);
            th.density = {rho, se};
            th.penetration_power = {rho * th.range_m, se * th.range_m};
            th.tau = {cfg_.sigma_t_per_density * rho * th.range_m, cfg_.sigma_t_per_density * se * th.range_m};
        } catch (const Error& e) {
            th.diagnosis += std::string(th.diagnosis.empty() ? "" : "; ") + "no density for S*: " + e.what();
        }
    }

    /// The reference group: named, or the fitted one with most beams.
    void chooseReference()
    {
        for (size_t g = 0; g < groups_.size(); ++g) {
            const auto& th = res_.thresholds[g];
            if (!cfg_.reference.empty()) {
                if (groups_[g].name == cfg_.reference) res_.reference = th.fitted ? int(g) : -1;
            } else if (th.fitted && (res_.reference < 0 || th.beams > res_.thresholds[size_t(res_.reference)].beams))
                res_.reference = int(g);
        }
        if (!cfg_.reference.empty() && res_.reference < 0)
            res_.diagnoses.push_back("the reference group '" + cfg_.reference + "' has no fitted threshold");
    }

    /// The two streams on the laser's times.
    void alignStreams()
    {
        for (size_t k = 0; k < K_; ++k) {
            AlignedScan a;
            a.time_s = log_.scans[k].time_s;
            a.saturation = S_at_[k];
            for (size_t g = 0; g < groups_.size(); ++g) {
                a.errors.push_back(gd_[g].counts.e[k]);
                a.beams.push_back(gd_[g].counts.n[k]);
                double sum = 0;
                int n = 0;
                for (double m : gd_[g].range_m[k])
                    if (!std::isnan(m)) {
                        sum += m;
                        ++n;
                    }
                a.mean_range_m.push_back(n ? sum / n : NAN);
            }
            res_.aligned.push_back(std::move(a));
        }
    }
};

}  // namespace

SensorFitResult fitSensor(const RecordedLog& log, const SaturationSeries& raw, const std::vector<BeamGroup>& groups,
                          const LrfSpec& spec, const CurveFitResult* calibration, const SensorFitConfig& cfg,
                          const FailureMask& failed)
{
    if (!(cfg.offset_window_s >= 0) || !(cfg.offset_step_s > 0))
        throw Error("--offset-window", "window must be >= 0 and step > 0");
    if (cfg.offset_window_s / cfg.offset_step_s > kMaxOffsetSteps)
        throw Error("--offset-window",
                    fmt("%g s in steps of %g s is more than %d offsets on each side", cfg.offset_window_s,
                        cfg.offset_step_s, kMaxOffsetSteps));
    if (raw.time_s.size() < 3)
        throw Error(raw.path, fmt("holds %zu saturation rows: a fit needs at least 3", raw.time_s.size()));
    if (groups.empty()) throw Error("fit", "no beam groups: give --scene or --surface/--surfaces");
    if (!(cfg.smooth_s >= 0)) throw Error("--smooth", "must be >= 0");
    if (cfg.bootstrap != 0 && (cfg.bootstrap < kMinBootstrapFits || cfg.bootstrap > 1000))
        throw Error("--bootstrap", "must be 0 (the analytic floor) or 10…1000 replicates");
    if (!failed.empty()) {
        bool shaped = failed.size() == log.scans.size();
        for (size_t k = 0; shaped && k < failed.size(); ++k) shaped = failed[k].size() == log.scans[k].range.size();
        if (!shaped) throw Error(log.path, "the failure mask does not have the log's scans and beams");
    }
    return SensorFit(log, groups, spec, calibration, cfg, failed).run(raw);
}

}  // namespace smokescan
