// fitSensor: recorded laser log + saturation series → clock offset, thresholds, penetration power,
// range bias/noise, with a diagnosis wherever the data cannot support a fit.
#include "smokescan/fit/sensor_fit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "smokescan/core/error.hpp"
#include "smokescan/core/order_stats.hpp"
#include "smokescan/plot/format.hpp"
#include "threshold_fit.hpp"

namespace smokescan {

RangeFit fitRangeBiasNoise(const std::string& group, const std::vector<std::vector<double>>& range_m,
                           const std::vector<double>& S, double S_clear_min, const SensorFitConfig& cfg);  // range_fit.cpp

namespace {

/// The series averaged over a centred window of 2h + 1 samples (shrunk at the ends). The fit needs
/// the saturation's slope in time to align the clocks; the raw series' slope between frames is
/// mostly noise.
SaturationSeries movingAverage(const SaturationSeries& s, int h)
{
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

/// Per group: the beams of the log it holds, and per scan the errors and valid ranges.
struct GroupData {
    std::vector<int> beams;
    detail::GroupCounts counts;                 ///< all scans
    std::vector<std::vector<double>> range_m;   ///< [scan][beam in group], NaN = error
};

/// Fraction of beams classified right by the best split of saturation, uncovered scans counting
/// one half (so a δ that pushes scans out of the camera's span gains nothing).
double agreement(const std::vector<GroupData>& gd, const SaturationSeries& sat, double delta, std::vector<double>* split)
{
    double correct = 0, total = 0;
    std::vector<std::pair<double, size_t>> order;
    for (size_t g = 0; g < gd.size(); ++g) {
        const auto& c = gd[g].counts;
        order.clear();
        for (size_t k = 0; k < c.t.size(); ++k) {
            total += c.n[k];
            const double S = saturationAt(sat, c.t[k] + delta);
            if (std::isnan(S)) correct += 0.5 * c.n[k];
            else order.emplace_back(S, k);
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

const char* errorLinkName(ErrorLink link)
{
    return link == ErrorLink::Logistic ? "logistic" : "probit";
}

SensorFitResult fitSensor(const RecordedLog& log, const SaturationSeries& raw, const std::vector<BeamGroup>& groups,
                          const LrfSpec& spec, const CurveFitResult* calibration, const SensorFitConfig& cfg)
{
    if (!(cfg.offset_window_s >= 0) || !(cfg.offset_step_s > 0)) throw Error("--offset-window", "window must be >= 0 and step > 0");
    if (groups.empty()) throw Error("fit", "no beam groups: give --scene or --surface/--surfaces");
    if (!(cfg.smooth_s >= 0)) throw Error("--smooth", "must be >= 0");
    SensorFitResult res;
    res.groups = groups;
    // The saturation, smoothed: its noise σ_S shrinks by √(2h + 1) and enters the width.
    std::vector<double> dt;
    for (size_t i = 1; i < raw.time_s.size(); ++i) dt.push_back(raw.time_s[i] - raw.time_s[i - 1]);
    const double frame_s = std::max(quantile(dt, 0.5), 1e-6);
    const double span_s = raw.time_s.empty() ? 0.0 : raw.time_s.back() - raw.time_s.front();
    if (cfg.smooth_s > span_s)
        throw Error("--smooth", "a window of " + fmt("%g", cfg.smooth_s) + " s is longer than the saturation series (" + fmt("%g", span_s) + " s)");
    const int h = int(std::min(std::floor(0.5 * cfg.smooth_s / frame_s + 1e-9), double(raw.time_s.size())));
    const SaturationSeries sat = movingAverage(raw, h);
    res.saturation_noise = detail::noiseOfSeries(raw.saturation);
    res.smoothing_samples = 2 * h + 1;
    const size_t K = log.scans.size();
    // Which beams each group holds (by the first scan's angles), and what each scan saw on them.
    std::vector<GroupData> gd(groups.size());
    const auto& a0 = log.scans.front().angle_rad;
    for (size_t g = 0; g < groups.size(); ++g)
        for (size_t i = 0; i < a0.size(); ++i)
            if (groups[g].contains(a0[i])) gd[g].beams.push_back(int(i));
    for (size_t g = 0; g < groups.size(); ++g) {
        auto& d = gd[g];
        for (const auto& s : log.scans) {
            int e = 0;
            std::vector<double> r;
            for (int i : d.beams) {
                const double m = s.range[size_t(i)] * log.unit_m;
                const bool err = spec.isErrorValue(std::llround(m / spec.unit_m));
                e += err;
                r.push_back(err ? NAN : m);
            }
            d.counts.t.push_back(s.time_s);
            d.counts.n.push_back(int(d.beams.size()));
            d.counts.e.push_back(e);
            d.range_m.push_back(std::move(r));
        }
    }
    std::vector<size_t> usable;  // groups with enough beams
    res.thresholds.resize(groups.size());
    res.ranges.resize(groups.size());
    for (size_t g = 0; g < groups.size(); ++g) {
        auto& th = res.thresholds[g];
        th.group = res.ranges[g].group = groups[g].name;
        th.beams = int(gd[g].beams.size());
        th.scans = int(K);
        for (size_t k = 0; k < K; ++k) {
            th.errors += gd[g].counts.e[k];
            th.observations += gd[g].counts.n[k];
        }
        if (th.beams < cfg.min_beams) th.diagnosis = "only " + std::to_string(th.beams) + " beams of the log fall in its angles";
        else usable.push_back(g);
    }
    // Do the clocks' spans meet for some offset in the window?
    const double t0 = log.scans.front().time_s, t1 = log.scans.back().time_s, c0 = sat.time_s.front(), c1 = sat.time_s.back();
    const double lo = cfg.estimate_offset ? cfg.offset_s - cfg.offset_window_s : cfg.offset_s;
    const double hi = cfg.estimate_offset ? cfg.offset_s + cfg.offset_window_s : cfg.offset_s;
    if (t1 + hi < c0 || t0 + lo > c1) {
        res.diagnoses.push_back(fmt("time spans do not overlap: laser %.1f-%.1f s, camera %.1f-%.1f s", t0, t1, c0, c1) +
                                (cfg.estimate_offset ? fmt(" for any offset within %.1f +/- %.1f s", cfg.offset_s, cfg.offset_window_s)
                                                     : fmt(" at offset %.1f s", cfg.offset_s)) +
                                "; give --offset (camera time - laser time)");
        return res;
    }
    // Degenerate groups: never an error, or nothing but errors.
    std::vector<size_t> fit_groups;
    double S_min = *std::min_element(sat.saturation.begin(), sat.saturation.end());
    double S_max = *std::max_element(sat.saturation.begin(), sat.saturation.end());
    for (size_t g : usable) {
        auto& th = res.thresholds[g];
        if (th.errors == 0) th.diagnosis = fmt("no error codes: the threshold lies below the lowest saturation seen (%.3f)", S_min);
        else if (th.errors == th.observations) th.diagnosis = fmt("every beam returned an error code: the threshold lies above the highest saturation seen (%.3f)", S_max);
        else fit_groups.push_back(g);
    }
    long long errs = 0, obs = 0;
    for (size_t g : usable) {
        errs += res.thresholds[g].errors;
        obs += res.thresholds[g].observations;
    }
    if (usable.empty()) res.diagnoses.push_back("no beam group has enough beams in the log");
    else if (errs == 0) res.diagnoses.push_back("no smoke event: no beam of any group returned an error code, so no threshold can be fitted");
    else if (errs == obs) res.diagnoses.push_back("all-error log: every beam returned an error code, so no threshold can be fitted");
    if (fit_groups.empty()) return res;

    // The clock offset: onsets and recoveries pin it; one transition alone cannot.
    std::vector<GroupData> fg;
    for (size_t g : fit_groups) fg.push_back(gd[g]);
    const double hold = std::max(1.0, 3 * spec.scan_period_s);
    const std::vector<double> trans = transitionTimes(fg, K, hold);
    res.offset.transitions = int(trans.size());
    const double first_t = trans.empty() ? NAN : trans.front();
    bool fit_offset = cfg.estimate_offset;
    if (fit_offset && res.offset.transitions < 2) {
        fit_offset = false;
        res.offset.diagnosis =
            res.offset.transitions == 1
                ? fmt("errors change state once only (at %.1f s) and never return: one crossing cannot tell the clock offset from the "
                      "threshold, so the offset is held at %.2f s (give --offset)", first_t, cfg.offset_s)
                : fmt("the error state never settles into an onset and a recovery: the offset is held at %.2f s (give --offset)", cfg.offset_s);
        res.diagnoses.push_back(res.offset.diagnosis);
    }
    std::vector<double> split(fg.size(), NAN);
    double delta0 = cfg.offset_s;
    if (fit_offset) {
        const int steps = int(std::ceil(cfg.offset_window_s / cfg.offset_step_s));
        double best = -1;
        int best_i = 0, best_j = 0;  // plateau of the maximum
        for (int i = -steps; i <= steps; ++i) {
            const double d = cfg.offset_s + i * cfg.offset_step_s, a = agreement(fg, sat, d, nullptr);
            res.offset.agreement.emplace_back(d, a);
            if (a > best + 1e-12) {
                best = a;
                best_i = best_j = i;
            } else if (a > best - 1e-12 && best_j == i - 1) best_j = i;
        }
        delta0 = cfg.offset_s + 0.5 * (best_i + best_j) * cfg.offset_step_s;
        res.offset.offset_s = {delta0, (best_j - best_i + 1) * cfg.offset_step_s / std::sqrt(12.0)};
        res.offset.estimated = true;  // refined below unless every group's step is sharp
        if (best_i == -steps || best_j == steps)
            res.diagnoses.push_back(fmt("the best clock offset lies at the edge of the search (%.1f s): widen --offset-window", delta0));
    } else {
        res.offset.offset_s = {cfg.offset_s, 0.0};
    }
    agreement(fg, sat, delta0, &split);

    // Sharp steps (errors and clear scans separate) have no width to fit: S* lies in the gap.
    detail::ThresholdProblem prob;
    prob.sat = &sat;
    prob.logistic = cfg.link == ErrorLink::Logistic;
    prob.fit_offset = fit_offset;
    prob.offset0 = delta0;
    prob.cluster_s = std::max({(2 * h + 2) * frame_s, 2 * spec.scan_period_s, 1e-3});
    prob.sigma_S = res.saturation_noise / std::sqrt(2.0 * h + 1);
    std::vector<size_t> smooth;
    for (size_t j = 0; j < fit_groups.size(); ++j) {
        const size_t g = fit_groups[j];
        detail::GroupCounts c;
        double err_max = -1, clean_min = 2;
        for (size_t k = 0; k < K; ++k) {
            const double S = saturationAt(sat, gd[g].counts.t[k] + delta0);
            if (std::isnan(S)) continue;
            c.t.push_back(gd[g].counts.t[k]);
            c.n.push_back(gd[g].counts.n[k]);
            c.e.push_back(gd[g].counts.e[k]);
            if (c.e.back() > 0) err_max = std::max(err_max, S);
            if (c.e.back() < c.n.back()) clean_min = std::min(clean_min, S);
        }
        auto& th = res.thresholds[g];
        th.dof = std::max(0, int(c.t.size()) - 2);
        if (err_max < 0 || clean_min > 1) {
            th.diagnosis = "within the camera's span the beams are all clear or all errors";
            continue;
        }
        if (err_max < clean_min) {
            th.fitted = th.sharp = true;
            th.S_star = {0.5 * (err_max + clean_min), (clean_min - err_max) / std::sqrt(12.0)};
            th.width = {0.0, NAN};
            th.diagnosis = fmt("sharp step: every scan below saturation %.4f had errors, none above %.4f; the width is below the "
                               "saturation's resolution", err_max, clean_min);
            continue;
        }
        prob.groups.push_back(std::move(c));
        prob.start.push_back({std::isfinite(split[j]) ? split[j] : 0.5 * (err_max + clean_min),
                              std::max(0.01, 0.05 * (S_max - S_min))});
        smooth.push_back(g);
    }
    if (!smooth.empty()) {
        const detail::ThresholdSolution sol = detail::solveThresholds(prob);
        if (fit_offset) res.offset = {true, {sol.offset, sol.offset_se}, res.offset.transitions, res.offset.agreement, res.offset.diagnosis};
        for (size_t j = 0; j < smooth.size(); ++j) {
            auto& th = res.thresholds[smooth[j]];
            th.fitted = sol.converged;
            if (!sol.converged) th.diagnosis = "the fit did not converge: " + sol.message;
            th.S_star = {sol.sw[j][0], std::sqrt(sol.cov[j](0, 0))};
            th.width = {sol.sw[j][1], std::sqrt(sol.cov[j](1, 1))};
            th.cov_S_star_width = sol.cov[j](0, 1);
            th.pearson_chi2 = sol.pearson_chi2[j];
            th.deviance = sol.deviance[j];
            th.variance_inflation = sol.inflation[j];
            th.dof = std::max(0, sol.nobs[j] - 2);
            if (prob.sigma_S == 0 && th.width.value <= 2 * detail::kMinWidth) {
                th.sharp = true;
                th.diagnosis = "the width reached its floor: the step is sharper than the data resolve";
            }
        }
    }
    const double delta = res.offset.offset_s.value;
    // What the data can say at most, whatever the likelihood's curvature claims: each onset or
    // recovery is timed only to the scan interval (uniform, Δt/√12) and read on a saturation of
    // noise σ_S; with slope dS/dt at the crossing, it fixes S* to √(σ_S² + (Ṡ·Δt)²/12) and the
    // offset to that over |Ṡ|. Combined over transitions, these floor the reported errors.
    {
        const double dt_scan = K > 1 ? (log.scans.back().time_s - log.scans.front().time_s) / double(K - 1) : spec.scan_period_s;
        const double half = std::max(1.0, 0.5 * cfg.smooth_s);
        double info_S = 0, info_t = 0;
        for (double t : trans) {
            const double a = saturationAt(sat, t + delta - half), b = saturationAt(sat, t + delta + half);
            if (std::isnan(a) || std::isnan(b)) continue;
            const double slope = (b - a) / (2 * half);
            const double var_S = prob.sigma_S * prob.sigma_S + slope * slope * dt_scan * dt_scan / 12;
            info_S += 1 / var_S;
            if (slope != 0) info_t += slope * slope / var_S;
        }
        if (info_t > 0 && res.offset.estimated)
            res.offset.offset_s.se = std::max(res.offset.offset_s.se, std::sqrt(1 / info_t));
        if (info_S > 0)
            for (size_t g : fit_groups) {
                auto& th = res.thresholds[g];
                if (th.fitted) th.S_star.se = std::max(th.S_star.se, std::sqrt(1 / info_S));
            }
    }

    // Penetration power and optical depth through the calibration curve; range bias and noise.
    std::vector<double> S_at(K);
    for (size_t k = 0; k < K; ++k) S_at[k] = saturationAt(sat, log.scans[k].time_s + delta);
    const double S_clear = quantile([&] {
        std::vector<double> v;
        for (double s : S_at)
            if (!std::isnan(s)) v.push_back(s);
        return v;
    }(), cfg.clear_quantile);
    for (size_t g : usable) {
        auto& th = res.thresholds[g];
        // Laser–surface distance: given, else the median valid range in clear air.
        th.range_m = groups[g].range_m;
        if (!(th.range_m > 0)) {
            std::vector<double> r;
            for (size_t k = 0; k < K; ++k)
                if (S_at[k] >= S_clear)
                    for (double m : gd[g].range_m[k])
                        if (!std::isnan(m)) r.push_back(m);
            th.range_m = quantile(r, 0.5);
        }
        if (th.fitted && calibration) {
            try {
                const auto [rho, se] = calibration->invert(th.S_star.value, th.S_star.se);
                th.density = {rho, se};
                th.penetration_power = {rho * th.range_m, se * th.range_m};
                th.tau = {cfg.sigma_t_per_density * rho * th.range_m, cfg.sigma_t_per_density * se * th.range_m};
            } catch (const Error& e) {
                th.diagnosis += std::string(th.diagnosis.empty() ? "" : "; ") + "no density for S*: " + e.what();
            }
        }
        double S_clear_min = S_clear;
        if (th.fitted && !th.sharp) S_clear_min = std::max(S_clear, th.S_star.value + 3 * th.width.value);
        res.ranges[g] = fitRangeBiasNoise(groups[g].name, gd[g].range_m, S_at, S_clear_min, cfg);
    }
    // The reference group: named, or the fitted one with most beams.
    for (size_t g = 0; g < groups.size(); ++g) {
        const auto& th = res.thresholds[g];
        if (!cfg.reference.empty()) {
            if (groups[g].name == cfg.reference) res.reference = th.fitted ? int(g) : -1;
        } else if (th.fitted && (res.reference < 0 || th.beams > res.thresholds[size_t(res.reference)].beams))
            res.reference = int(g);
    }
    if (!cfg.reference.empty() && res.reference < 0)
        res.diagnoses.push_back("the reference group '" + cfg.reference + "' has no fitted threshold");
    // The two streams on the laser's times.
    for (size_t k = 0; k < K; ++k) {
        AlignedScan a;
        a.time_s = log.scans[k].time_s;
        a.saturation = S_at[k];
        for (size_t g = 0; g < groups.size(); ++g) {
            a.errors.push_back(gd[g].counts.e[k]);
            a.beams.push_back(gd[g].counts.n[k]);
            double sum = 0;
            int n = 0;
            for (double m : gd[g].range_m[k])
                if (!std::isnan(m)) {
                    sum += m;
                    ++n;
                }
            a.mean_range_m.push_back(n ? sum / n : NAN);
        }
        res.aligned.push_back(std::move(a));
    }
    return res;
}

}  // namespace smokescan
