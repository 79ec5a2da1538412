#include "candidate_fit.hpp"

#include <ceres/ceres.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include "causes.hpp"
#include "ceres_fit.hpp"

namespace smokescan::detail {
namespace {

/// Observations [begin, end) of fixed chunks, each chunk handed to `each(chunk, begin, end)` on
/// some thread: what a chunk adds up is the same whatever the thread count.
constexpr size_t kChunk = 4096;
size_t chunksOf(size_t n) { return (n + kChunk - 1) / kChunk; }
template <class F>
void forChunks(size_t n, F&& each)
{
    tbb::parallel_for(size_t(0), chunksOf(n), [&](size_t c) { each(c, c * kChunk, std::min(n, (c + 1) * kChunk)); });
}

/// A deterministic parallel sum: fixed chunks summed in parallel, then added in order.
template <class F>
void chunkedSum(size_t n, double* value, double* grad, F&& term)
{
    const size_t chunks = chunksOf(n);
    std::vector<double> v(chunks, 0.0), g(chunks, 0.0);
    forChunks(n, [&](size_t c, size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
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

/// Observations a fit keeps an ObsMemo for (88 bytes each: about 350 MB); a larger fit runs
/// without (the same doubles, recomputed).
constexpr size_t kMemoObservations = 4'000'000;

/// The candidate's negative log-likelihood over a set of observations, for Ceres.
class CandidateNll : public ceres::FirstOrderFunction {
public:
    CandidateNll(const Replay& r, const ReplayModel& m, const Candidate& c, const std::vector<Obs>& obs)
        : r_(r), m_(m), c_(c), obs_(obs), memo_(obs.size() <= kMemoObservations ? obs.size() : 0)
    {
    }
    bool Evaluate(const double* theta, double* cost, double* gradient) const override
    {
        const CandidateAt at(r_, m_, c_, J(theta[0], 0));
        double ll = 0, g = 0;
        chunkedSum(obs_.size(), &ll, &g,
                   [&](size_t i) { return at.logLik(obs_[i], memo_.empty() ? nullptr : &memo_[i]); });
        *cost = -ll;
        if (gradient) gradient[0] = -g;
        return std::isfinite(ll);
    }
    int NumParameters() const override { return 1; }

    /// @brief The observed information at θ, by central differences of the analytic gradient at
    /// θ ± h, and each block's score added to `score`: the mean of its gradients at θ ± h (the
    /// score at θ within O(h²)). One parallel pass, two evaluations an observation; deterministic
    /// (fixed chunks, added in order).
    double informationAndScores(double theta, double h, std::map<int, double>& score) const
    {
        const CandidateAt up(r_, m_, c_, J(theta + h, 0)), down(r_, m_, c_, J(theta - h, 0));
        const size_t chunks = chunksOf(obs_.size());
        std::vector<double> rise(chunks, 0.0);
        std::vector<std::vector<std::pair<int, double>>> runs(chunks);  // (block, score) as met
        forChunks(obs_.size(), [&](size_t c, size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) {
                ObsMemo* memo = memo_.empty() ? nullptr : &memo_[i];
                const double g_up = up.logLik(obs_[i], memo).v[0], g_down = down.logLik(obs_[i], memo).v[0];
                rise[c] += g_up - g_down;
                const int block = r_.scans[size_t(obs_[i].k)].block;
                if (runs[c].empty() || runs[c].back().first != block) runs[c].emplace_back(block, 0.0);
                runs[c].back().second += 0.5 * (g_up + g_down);
            }
        });
        double total = 0;
        for (size_t c = 0; c < chunks; ++c) {
            total += rise[c];
            for (const auto& [block, s] : runs[c]) score[block] += s;
        }
        return -total / (2 * h);  // of the negative log-likelihood
    }

private:
    const Replay& r_;
    const ReplayModel& m_;
    const Candidate& c_;
    const std::vector<Obs>& obs_;
    /// Each observation's, written only by the evaluation of that observation: one thread at a time.
    mutable std::vector<ObsMemo> memo_;
};

/// Ends a fit whose θ has walked below the row's nil_below (a width or share sliding to zero).
class StopWhenNil : public ceres::IterationCallback {
public:
    StopWhenNil(double below, const double* theta) : below_(below), theta_(theta) {}
    ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override
    {
        return *theta_ < below_ ? ceres::SOLVER_TERMINATE_SUCCESSFULLY : ceres::SOLVER_CONTINUE;
    }

private:
    double below_;
    const double* theta_;
};

}  // namespace

ThetaFit fitCandidate(const Replay& r, const ReplayModel& m, const Candidate& c, const std::vector<Obs>& obs,
                      const std::vector<double>* starts)
{
    ThetaFit f;
    if (obs.empty()) return f;
    auto* nll = new CandidateNll(r, m, c, obs);
    ceres::GradientProblem problem(nll);  // owns nll
    // The starts are ranked on every kRankStride-th observation when there are many (every scan
    // keeps its share of beams): about half of a diagnosis's likelihood passes were spent ranking
    // starts, and a start only chooses the basin the full fit then descends. On a rugged
    // likelihood (the clock offset's, a basin a camera frame, a few nats apart: its row's
    // jackknife) the three best are ranked again on all of them, which the subsample's noise could swap.
    constexpr size_t kRankStride = 4, kRankAll = 20000;
    const size_t finalists = causeRow(c.cause).jackknife ? 3 : 0;
    std::vector<Obs> ranked;
    if (obs.size() > kRankAll)
        for (size_t i = 0; i < obs.size(); i += kRankStride) ranked.push_back(obs[i]);
    ceres::GradientProblem ranking(new CandidateNll(r, m, c, ranked.empty() ? obs : ranked));
    const std::vector<double>& from = starts && !starts->empty() ? *starts : c.starts();
    auto costOn = [](const ceres::GradientProblem& p, double t) {
        double cost = kInf;
        return p.Evaluate(&t, &cost, nullptr) && std::isfinite(cost) ? cost : kInf;
    };
    std::vector<std::pair<double, double>> tried;  // (cost on the subsample, start)
    double theta = from[bestStart(from, [&](double t) {
        tried.emplace_back(costOn(ranking, t), t);
        return tried.back().first;
    })];
    if (!ranked.empty() && finalists > 0) {
        std::stable_sort(tried.begin(), tried.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        double best = kInf;
        for (size_t k = 0; k < std::min(finalists, tried.size()); ++k) {
            const double cost = costOn(problem, tried[k].second);
            if (cost < best) best = cost, theta = tried[k].second;
        }
    } else if (const double nil = causeRow(c.cause).nil_below;
               std::isfinite(nil) && theta == *std::min_element(from.begin(), from.end())) {
        // The lowest start is the best: the optimum may be the boundary (no width, no share), which
        // the fit would reach walking θ down a vanishing gradient, a fixed step at a time (about
        // 20 passes over the observations from a width's lowest start to its nil). It is the
        // boundary (a likelihood with one optimum) when the cost falls from the lowest start
        // towards the nil (its slope there is not negative), the nil costs no more, and the cost
        // still falls towards it there: the fit then starts at the nil and ends at once. Not when
        // the cost rises towards it, or is flat there (a sharp threshold's Φ underflows): an
        // optimum may lie between, which the fit walks down to (from the nil, the gradient is below
        // the solver's tolerance and it would stop at once); nor when it rises from the lowest
        // start towards the nil (an optimum above the lowest start).
        double at_theta = kInf, at_nil = kInf, slope_theta = 0, slope_nil = 0;
        if (ranking.Evaluate(&theta, &at_theta, &slope_theta) && slope_theta >= 0 &&
            ranking.Evaluate(&nil, &at_nil, &slope_nil) && at_nil <= at_theta && slope_nil > 0)
            theta = nil;
    }
    ceres::GradientProblemSolver::Options opt;
    opt.line_search_direction_type = ceres::LBFGS;
    opt.max_num_iterations = 100;
    opt.function_tolerance = 1e-10;
    opt.gradient_tolerance = 1e-8;
    StopWhenNil stop(causeRow(c.cause).nil_below, &theta);
    opt.update_state_every_iteration = true;  // the callback reads θ
    opt.callbacks.push_back(&stop);
    ceres::GradientProblemSolver::Summary summary;
    ceres::Solve(opt, problem, &theta, &summary);
    if (!summary.IsSolutionUsable() || !std::isfinite(theta) || !c.plausible(r, theta, m)) return f;
    // Observed information by central differences of the analytic gradient; scores per block.
    std::map<int, double> score;
    const double info = nll->informationAndScores(theta, 1e-4 * std::max(1.0, std::abs(theta)), score);
    double meat = 0;
    for (const auto& [blk, s] : score) meat += s * s;
    const double blocks = double(score.size()), corr = blocks > 1 ? blocks / (blocks - 1) : 1.0;
    if (info > 0) f.se = std::sqrt(std::max(1 / info, corr * meat / (info * info)));
    f.theta = theta;
    f.ok = true;
    return f;
}

size_t bestStart(const std::vector<double>& starts, const std::function<double(double)>& cost)
{
    constexpr size_t kStride = 2, kLong = 24, kBasins = 3;
    const size_t n = starts.size();
    std::vector<double> c(n, NAN);  // NaN: not evaluated
    auto at = [&](size_t i) {
        if (std::isnan(c[i])) {
            const double v = cost(starts[i]);
            c[i] = std::isfinite(v) ? v : kInf;
        }
        return c[i];
    };
    auto best = [&] {
        size_t b = 0;
        for (size_t i = 0; i < n; ++i)
            if (!std::isnan(c[i]) && (std::isnan(c[b]) || c[i] < c[b])) b = i;
        return b;
    };
    if (n <= kLong) {
        for (size_t i = 0; i < n; ++i) at(i);
        return best();
    }
    std::vector<size_t> coarse;
    for (size_t i = 0; i < n; i += kStride) coarse.push_back(i);
    if (coarse.back() != n - 1) coarse.push_back(n - 1);
    for (size_t i : coarse) at(i);
    // The starts between the neighbours of the kBasins best coarse ones (all of them when no
    // coarse start has a finite cost).
    std::vector<size_t> order = coarse;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return c[a] < c[b]; });
    const bool none = !std::isfinite(c[order.front()]);
    for (size_t k = 0; k < (none ? order.size() : std::min(kBasins, order.size())); ++k) {
        const size_t i = order[k], lo = i >= kStride ? i - kStride + 1 : 0, hi = std::min(n - 1, i + kStride - 1);
        for (size_t j = lo; j <= hi; ++j) at(j);
    }
    return best();
}

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

}  // namespace smokescan::detail

namespace smokescan::detail {

double jackknifeSe(const Replay& r, const ReplayModel& m, const Candidate& c, double theta, int groups)
{
    // Each group is every groups-th block; θ refitted without it, started near the full fit.
    std::vector<double> starts;
    for (int i = -8; i <= 8; ++i) starts.push_back(theta + 0.125 * i);
    const std::vector<Obs> all = touched(r, c, -1);
    std::vector<double> thetas;
    for (int g = 0; g < groups; ++g) {
        std::vector<Obs> kept;
        for (const Obs& o : all)
            if (r.scans[size_t(o.k)].block % groups != g) kept.push_back(o);
        if (kept.size() == all.size()) continue;  // an empty group (fewer blocks than groups)
        const ThetaFit f = fitCandidate(r, m, c, kept, &starts);
        if (f.ok) thetas.push_back(f.theta);
    }
    if (thetas.size() < 2) return NAN;
    double mean = 0, ss = 0;
    for (double t : thetas) mean += t / double(thetas.size());
    for (double t : thetas) ss += (t - mean) * (t - mean);
    const double n = double(thetas.size());
    return std::sqrt((n - 1) / n * ss);
}

}  // namespace smokescan::detail
