#include "smokescan/diagnose/diagnosis.hpp"

#include <ceres/ceres.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "../calib/ceres_fit.hpp"
#include "candidates.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/random.hpp"

namespace smokescan {
namespace {

using detail::Candidate;
using detail::Cause;
using detail::J;
using detail::Obs;

/// A deterministic parallel sum: fixed chunks summed in parallel, then added in order.
template <class F>
void chunkedSum(size_t n, double* value, double* grad, F&& term)
{
    constexpr size_t kChunk = 4096;
    const size_t chunks = (n + kChunk - 1) / kChunk;
    std::vector<double> v(chunks, 0.0), g(chunks, 0.0);
    tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
        for (size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i) {
            const J t = term(i);
            v[c] += t.a;
            g[c] += t.v[0];
        }
    });
    *value = 0;
    if (grad) *grad = 0;
    for (size_t c = 0; c < chunks; ++c) {
        *value += v[c];
        if (grad) *grad += g[c];
    }
}

/// The candidate's negative log-likelihood over a set of observations, for Ceres.
class CandidateNll : public ceres::FirstOrderFunction {
public:
    CandidateNll(const Replay& r, const Extensions& m, const Candidate& c, const std::vector<Obs>& obs)
        : r_(r), m_(m), c_(c), obs_(obs)
    {
    }
    bool Evaluate(const double* theta, double* cost, double* gradient) const override
    {
        J th(theta[0], 0);
        double ll = 0, g = 0;
        chunkedSum(obs_.size(), &ll, &g, [&](size_t i) { return detail::candidateLogLik(r_, m_, c_, obs_[i], th); });
        *cost = -ll;
        if (gradient) gradient[0] = -g;
        return std::isfinite(ll);
    }
    int NumParameters() const override { return 1; }

private:
    const Replay& r_;
    const Extensions& m_;
    const Candidate& c_;
    const std::vector<Obs>& obs_;
};

/// A candidate's maximum-likelihood θ on a set of observations, with its standard error (the
/// larger of the observed information's and the sandwich's over time blocks).
struct ThetaFit {
    bool ok = false;
    double theta = 0, se = NAN;
};

ThetaFit fitCandidate(const Replay& r, const Extensions& m, const Candidate& c, const std::vector<Obs>& obs)
{
    ThetaFit f;
    if (obs.empty()) return f;
    ceres::GradientProblem problem(new CandidateNll(r, m, c, obs));
    double theta = c.theta_start, best = kInf;
    for (double t : c.starts()) {
        double cost = kInf;
        if (problem.Evaluate(&t, &cost, nullptr) && cost < best) {
            best = cost;
            theta = t;
        }
    }
    ceres::GradientProblemSolver::Options opt;
    opt.line_search_direction_type = ceres::LBFGS;
    opt.max_num_iterations = 100;
    opt.function_tolerance = 1e-10;
    opt.gradient_tolerance = 1e-8;
    ceres::GradientProblemSolver::Summary summary;
    detail::quietCeres();
    ceres::Solve(opt, problem, &theta, &summary);
    if (!summary.IsSolutionUsable() || !std::isfinite(theta)) return f;
    // Observed information by central differences of the analytic gradient; scores per block.
    auto gradAt = [&](double t) {
        double cost = 0, g = 0;
        problem.Evaluate(&t, &cost, &g);
        return g;
    };
    const double h = 1e-4 * std::max(1.0, std::abs(theta));
    const double info = (gradAt(theta + h) - gradAt(theta - h)) / (2 * h);
    std::map<int, double> score;
    const J th(theta, 0);
    for (const Obs& o : obs) score[r.scans[size_t(o.k)].block] += detail::candidateLogLik(r, m, c, o, th).v[0];
    double meat = 0;
    for (const auto& [blk, s] : score) meat += s * s;
    const double blocks = double(score.size()), corr = blocks > 1 ? blocks / (blocks - 1) : 1.0;
    if (info > 0) f.se = std::sqrt(std::max(1 / info, corr * meat / (info * info)));
    f.theta = theta;
    f.ok = true;
    return f;
}

/// The observations a candidate touches, in fold `fold` (−1: all).
std::vector<Obs> touched(const Replay& r, const Candidate& c, int fold)
{
    std::vector<int> beams;
    for (size_t b = 0; b < r.beams.size(); ++b)
        if (c.touches(r, int(b))) beams.push_back(int(b));
    std::vector<Obs> obs;
    for (size_t k = 0; k < r.scans.size(); ++k) {
        if (fold >= 0 && r.scans[k].block % 2 != fold) continue;
        for (int b : beams) obs.push_back({int(k), b});
    }
    return obs;
}

/// One-sided sign-flip p-value of the blocks' gains summing to at least their observed total.
double signFlipP(const std::vector<double>& gains, long long flips, uint64_t seed)
{
    std::vector<double> g;
    for (double x : gains)
        if (x != 0) g.push_back(x);
    if (g.empty()) return 1.0;
    double total = 0;
    for (double x : g) total += x;
    const double tol = 1e-12 * (1 + std::abs(total));
    long long hits = 0, n = 0;
    if (g.size() <= 20) {
        const long long N = 1LL << g.size();
        for (long long mask = 0; mask < N; ++mask) {
            double s = 0;
            for (size_t i = 0; i < g.size(); ++i) s += (mask >> i & 1) ? -g[i] : g[i];
            hits += s >= total - tol;
        }
        n = N;
    } else {
        KeyedRng rng(seed, 0x5f1, 0);
        for (long long it = 0; it < flips; ++it) {
            double s = 0;
            for (double x : g) s += rng.uniform() < 0.5 ? -x : x;
            hits += s >= total - tol;
        }
        hits += 1;  // the observed signs themselves
        n = flips + 1;
    }
    return double(hits) / double(n);
}

/// A candidate's cross-fitted held-out gains per block, with each fold's fit.
struct Scored {
    Candidate c;
    std::vector<double> block_gain;
    double gain = 0;
    long long obs = 0;
    double p = 1;
    ThetaFit fold_fit[2];
};

Scored scoreCandidate(const Replay& r, const Extensions& m, Candidate c, const DiagnosisConfig& cfg)
{
    Scored s;
    s.block_gain.assign(size_t(r.blocks()), 0.0);
    for (int fold = 0; fold < 2; ++fold) {
        Candidate cf = c;
        if (c.cause == Cause::SectorDropout && !detail::findDropoutSector(r, m, fold, cf.from_rad, cf.to_rad)) continue;
        const ThetaFit f = fitCandidate(r, m, cf, touched(r, cf, fold));
        s.fold_fit[fold] = f;
        if (!f.ok) continue;
        const J th(f.theta, 0);
        for (const Obs& o : touched(r, cf, 1 - fold)) {
            const double gain = detail::candidateLogLik(r, m, cf, o, th).a - detail::modelLogLik(r, m, o);
            s.block_gain[size_t(r.scans[size_t(o.k)].block)] += gain;
            ++s.obs;
        }
    }
    for (double g : s.block_gain) s.gain += g;
    // Only a candidate large enough to be accepted needs its p-value (the sign flips cost).
    s.p = s.obs > 0 && s.gain >= cfg.min_gain * double(s.obs) ? signFlipP(s.block_gain, cfg.sign_flips, cfg.seed) : 1.0;
    s.c = c;
    return s;
}

/// The round's candidates: every cause, each surface for the per-surface ones.
std::vector<Candidate> candidates(const Replay& r, const Extensions& m, const DiagnosisConfig& cfg,
                                  const std::vector<Finding>& found)
{
    auto taken = [&](const Candidate& c) {
        for (const auto& f : found)
            if (f.cause == detail::causeName(c.cause) && f.target == c.target(r)) return true;
        return false;
    };
    std::map<int, int> beams_on;
    for (const auto& b : r.beams)
        if (b.surface >= 0) ++beams_on[b.surface];
    std::vector<Candidate> out;
    auto add = [&](Candidate c) {
        if (!taken(c)) out.push_back(c);
    };
    if (r.from_saturation) add({Cause::ClockOffset, -1, 0, 0, 0.0, 0.0});
    for (const auto& [s, n] : beams_on)
        if (n >= cfg.min_beams) add({Cause::SurfaceThreshold, s, 0, 0, 0.0, 0.0});
    add({Cause::ThresholdWidth, -1, 0, 0, std::log(m.width), std::log(std::max(m.width, 0.1))});
    for (const auto& [s, n] : beams_on)
        if (n >= cfg.min_beams) add({Cause::SurfaceRangeBias, s, 0, 0, 0.0, 0.0});
    add({Cause::RangeNoiseGrowth, -1, 0, 0, 0.0, 1.0});
    add({Cause::SmokeObstacleReturn, -1, 0, 0, -40.0, -3.0});
    Candidate sector{Cause::SectorDropout, -1, 0, 0, -40.0, -2.0};
    if (detail::findDropoutSector(r, m, -1, sector.from_rad, sector.to_rad)) add(sector);
    add({Cause::Hysteresis, -1, 0, 0, 0.0, 0.0});
    return out;
}

/// An accepted candidate: its all-data fit, each fold's fit, and the finding reported.
struct Accepted {
    Candidate c;
    ThetaFit all;
    double fold_theta[2] = {0, 0};
    Finding f;
};

Accepted accept(const Replay& r, const Extensions& m, const Scored& s)
{
    Accepted a;
    a.c = s.c;
    a.all = fitCandidate(r, m, s.c, touched(r, s.c, -1));
    for (int fold = 0; fold < 2; ++fold)
        a.fold_theta[fold] = s.fold_fit[fold].ok ? s.fold_fit[fold].theta : a.all.theta;
    a.f.cause = detail::causeName(s.c.cause);
    a.f.target = s.c.target(r);
    a.f.parameters = s.c.report(a.all.theta, a.all.se);
    a.f.loglik_gain = s.gain;
    a.f.loglik_gain_per_beam = s.obs > 0 ? s.gain / double(s.obs) : 0.0;
    a.f.p_value = s.p;
    for (double g : s.block_gain) a.f.blocks += g != 0;
    return a;
}

/// The figures with model m_f predicting the scans of fold f (held out from its fit).
std::vector<ModelFigures> foldFigures(const Replay& r, const Extensions& m0, const Extensions& m1)
{
    std::map<std::string, ModelFigures> per;
    ModelFigures all;
    double sse_all = 0;
    long long n_rmse_all = 0;
    std::map<std::string, std::pair<double, long long>> sse;
    std::map<std::string, std::pair<long long, long long>> rec;  // recorded errors, ranges
    auto add = [&](ModelFigures& f, double ll, bool err, double p_err, double resid, std::pair<double, long long>& s,
                   std::pair<long long, long long>& rc) {
        ++f.beams;
        f.loglik_per_beam += ll;
        if (err) {
            ++rc.first;
            f.missed_error_rate += p_err < 0.5;
        } else {
            ++rc.second;
            f.invented_error_rate += p_err >= 0.5;
            if (p_err < 0.5) {
                s.first += resid * resid;
                ++s.second;
            }
        }
    };
    std::pair<double, long long> s_all{0, 0};
    std::pair<long long, long long> rc_all{0, 0};
    for (size_t k = 0; k < r.scans.size(); ++k)
        for (size_t b = 0; b < r.beams.size(); ++b) {
            if (r.beams[b].surface < 0) continue;
            const Obs o{int(k), int(b)};
            const Extensions& m = r.scans[k].block % 2 == 0 ? m0 : m1;
            const double ll = detail::modelLogLik(r, m, o);
            const auto [p_err, mu] = detail::modelPrediction(r, m, o);
            const float v = r.range_m[k][b];
            const bool err = std::isnan(v);
            const std::string& name = r.surface_names[size_t(r.beams[b].surface)];
            ModelFigures& f = per[name];
            f.surface = name;
            add(f, ll, err, p_err, err ? 0.0 : v - mu, sse[name], rec[name]);
            add(all, ll, err, p_err, err ? 0.0 : v - mu, s_all, rc_all);
        }
    auto finish = [](ModelFigures& f, const std::pair<double, long long>& s,
                     const std::pair<long long, long long>& rc) {
        if (f.beams > 0) f.loglik_per_beam /= double(f.beams);
        f.missed_error_rate = rc.first > 0 ? f.missed_error_rate / double(rc.first) : 0.0;
        f.invented_error_rate = rc.second > 0 ? f.invented_error_rate / double(rc.second) : 0.0;
        f.range_rmse_m = s.second > 0 ? std::sqrt(s.first / double(s.second)) : NAN;
    };
    finish(all, s_all, rc_all);
    (void)sse_all;
    (void)n_rmse_all;
    std::vector<ModelFigures> out{all};
    for (auto& [name, f] : per) {
        finish(f, sse[name], rec[name]);
        out.push_back(f);
    }
    return out;
}

}  // namespace

std::vector<ModelFigures> modelFigures(const Replay& r, const Extensions& m) { return foldFigures(r, m, m); }

DiagnosisResult diagnose(const Replay& r, const DiagnosisConfig& cfg)
{
    DiagnosisResult res;
    res.blocks = r.blocks();
    if (res.blocks < 4)
        throw Error("diagnose",
                    "the run spans " + std::to_string(res.blocks) +
                        " time blocks; at least 4 are needed to hold some out (a longer run, or a shorter --block)");
    double max_density = 0;
    for (const auto& s : r.scans) max_density = std::max(max_density, s.density);
    if (!(max_density > 0)) throw Error("diagnose", "the run holds no smoke: nothing to diagnose");
    for (const auto& b : r.beams)
        if (b.surface >= 0) res.observations += (long long)r.scans.size();
    res.baseline = modelFigures(r, res.model);
    std::vector<Accepted> acc;
    for (int round = 1; round <= cfg.max_findings; ++round) {
        const std::vector<Candidate> cands = candidates(r, res.model, cfg, res.findings);
        if (cands.empty()) break;
        std::vector<Scored> scored;
        for (const Candidate& c : cands) scored.push_back(scoreCandidate(r, res.model, c, cfg));
        // Bonferroni in two families, α/2 each: the global causes (few) and the targeted ones (a
        // surface or a sector each), so that the many targets do not drown a global cause.
        int n_global = 0;
        for (const Candidate& c : cands) n_global += c.target(r).empty();
        const int n_targeted = int(cands.size()) - n_global;
        const Scored* best = nullptr;
        for (const Scored& s : scored) {
            res.tried.push_back({round, detail::causeName(s.c.cause), s.c.target(r), s.gain, s.p});
            const bool global = s.c.target(r).empty();
            const double level = 0.5 * cfg.alpha / double(std::max(1, global ? n_global : n_targeted));
            const bool large = s.obs > 0 && s.gain >= cfg.min_gain * double(s.obs);
            if (s.p < level && large && (!best || s.gain > best->gain)) best = &s;
        }
        if (!best) break;
        Accepted a = accept(r, res.model, *best);
        if (!a.all.ok) break;
        a.c.commit(a.all.theta, res.model);
        res.findings.push_back(a.f);
        acc.push_back(a);
    }
    // Backward check: a finding that the later ones explain (a width absorbing a hysteresis found
    // after it) no longer gains on held-out data on top of the others, and is dropped; the rest
    // are refitted in order.
    for (bool dropped = true; dropped && acc.size() > 1;) {
        dropped = false;
        for (size_t i = 0; i < acc.size() && !dropped; ++i) {
            Extensions others;
            for (size_t j = 0; j < acc.size(); ++j)
                if (j != i) acc[j].c.commit(acc[j].all.theta, others);
            const Scored s = scoreCandidate(r, others, acc[i].c, cfg);
            if (s.p < cfg.alpha / double(acc.size()) && s.obs > 0 && s.gain >= cfg.min_gain * double(s.obs)) continue;
            acc.erase(acc.begin() + long(i));
            dropped = true;
        }
        if (!dropped) break;
        res.model = Extensions{};
        res.findings.clear();
        std::vector<Accepted> kept;
        for (const Accepted& prev : acc) {
            Accepted a = accept(r, res.model, scoreCandidate(r, res.model, prev.c, cfg));
            if (!a.all.ok) continue;  // a refit that fails drops the finding rather than commit a null θ
            a.c.commit(a.all.theta, res.model);
            res.findings.push_back(a.f);
            kept.push_back(a);
        }
        acc = kept;
    }
    Extensions fold_model[2];  // fold_model[f]: fitted without fold f, predicts its scans
    for (const Accepted& a : acc)
        for (int fold = 0; fold < 2; ++fold) a.c.commit(a.fold_theta[fold], fold_model[1 - fold]);
    res.extended = foldFigures(r, fold_model[0], fold_model[1]);
    for (const auto& f : res.findings)
        res.verdict += (res.verdict.empty() ? "" : ", ") + f.cause + (f.target.empty() ? "" : " (" + f.target + ")");
    if (res.verdict.empty()) res.verdict = "none";
    return res;
}

}  // namespace smokescan
