#include "candidate_fit.hpp"

#include <ceres/ceres.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "ceres_fit.hpp"

namespace smokescan::detail {
namespace {

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
    CandidateNll(const Replay& r, const ReplayModel& m, const Candidate& c, const std::vector<Obs>& obs)
        : r_(r), m_(m), c_(c), obs_(obs)
    {
    }
    bool Evaluate(const double* theta, double* cost, double* gradient) const override
    {
        const CandidateAt at(r_, m_, c_, J(theta[0], 0));
        double ll = 0, g = 0;
        chunkedSum(obs_.size(), &ll, &g, [&](size_t i) { return at.logLik(obs_[i]); });
        *cost = -ll;
        if (gradient) gradient[0] = -g;
        return std::isfinite(ll);
    }
    int NumParameters() const override { return 1; }

private:
    const Replay& r_;
    const ReplayModel& m_;
    const Candidate& c_;
    const std::vector<Obs>& obs_;
};

/// The start of least cost. A long grid of starts (the clock offset's 97) is searched coarse to
/// fine: every kStride-th start, then the starts between the best one's neighbours; a basin
/// narrower than kStride steps could be passed over, which a smooth likelihood on that scale
/// (the clock offset's: smoke ramps of seconds, steps of a camera frame) does not have.
double bestStart(const ceres::GradientProblem& problem, const std::vector<double>& from)
{
    constexpr size_t kStride = 4, kLong = 24;
    const size_t stride = from.size() > kLong ? kStride : 1;
    size_t best_i = 0;
    double best = kInf;
    auto tryStart = [&](size_t i) {
        double t = from[i], cost = kInf;
        if (problem.Evaluate(&t, &cost, nullptr) && cost < best) best = cost, best_i = i;
    };
    for (size_t i = 0; i < from.size(); i += stride) tryStart(i);
    if (stride > 1) {
        if ((from.size() - 1) % stride != 0) tryStart(from.size() - 1);
        const size_t coarse = best_i, lo = coarse >= stride ? coarse - stride + 1 : 0,
                     hi = std::min(from.size() - 1, coarse + stride - 1);
        for (size_t i = lo; i <= hi; ++i)
            if (i != coarse) tryStart(i);
    }
    return from[best_i];
}

}  // namespace

ThetaFit fitCandidate(const Replay& r, const ReplayModel& m, const Candidate& c, const std::vector<Obs>& obs,
                      const std::vector<double>* starts)
{
    ThetaFit f;
    if (obs.empty()) return f;
    ceres::GradientProblem problem(new CandidateNll(r, m, c, obs));
    const std::vector<double>& from = starts && !starts->empty() ? *starts : c.starts();
    double theta = bestStart(problem, from);
    ceres::GradientProblemSolver::Options opt;
    opt.line_search_direction_type = ceres::LBFGS;
    opt.max_num_iterations = 100;
    opt.function_tolerance = 1e-10;
    opt.gradient_tolerance = 1e-8;
    ceres::GradientProblemSolver::Summary summary;
    ceres::Solve(opt, problem, &theta, &summary);
    if (!summary.IsSolutionUsable() || !std::isfinite(theta) || !c.plausible(r, theta, m)) return f;
    // Observed information by central differences of the analytic gradient; scores per block.
    auto gradAt = [&](double t) {
        double cost = 0, g = 0;
        problem.Evaluate(&t, &cost, &g);
        return g;
    };
    const double h = 1e-4 * std::max(1.0, std::abs(theta));
    const double info = (gradAt(theta + h) - gradAt(theta - h)) / (2 * h);
    std::map<int, double> score;
    const CandidateAt at(r, m, c, J(theta, 0));
    for (const Obs& o : obs) score[r.scans[size_t(o.k)].block] += at.logLik(o).v[0];
    double meat = 0;
    for (const auto& [blk, s] : score) meat += s * s;
    const double blocks = double(score.size()), corr = blocks > 1 ? blocks / (blocks - 1) : 1.0;
    if (info > 0) f.se = std::sqrt(std::max(1 / info, corr * meat / (info * info)));
    f.theta = theta;
    f.ok = true;
    return f;
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
