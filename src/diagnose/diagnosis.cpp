#include "smokescan/diagnose/diagnosis.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "candidate_fit.hpp"
#include "candidates.hpp"
#include "causes.hpp"
#include "sign_flip.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/random.hpp"

namespace smokescan {
namespace {

using detail::Candidate;
using detail::Cause;
using detail::fitCandidate;
using detail::J;
using detail::Obs;
using detail::ReplayModel;
using detail::signFlipP;
using detail::ThetaFit;
using detail::touched;

/// The models of the search: `all` fitted on every block (reported), and fold[f] fitted on fold
/// f's blocks only (it predicts fold 1 − f): each round scores its candidates on top of the model
/// of the fold it was fitted on, so no block's gain depends on a fit that saw it.
struct Models {
    ReplayModel all, fold[2];
    Models(const Replay& r, const ModelExtensions& prior)
        : all(r, prior), fold{ReplayModel(r, prior), ReplayModel(r, prior)}
    {
    }
};

/// A candidate's cross-fitted held-out gains per block, with each fold's fit and target.
struct Scored {
    Candidate c;
    Candidate fold_c[2];  ///< the candidate as fitted on each fold (a sector is found per fold)
    std::vector<double> block_gain;
    double gain = 0;
    long long obs = 0;
    double p = NAN;  ///< the sign-flip test's; NaN when not tested (no gain, or below the floor)
    ThetaFit fold_fit[2];
    double effect = 0;  ///< the size of the folds' mean θ, in its row's floor units
    double effect_se = NAN;  ///< its standard error on all the data (the folds' over √2)
    double blocks_eff = 0;  ///< the blocks its gain is spread over: (Σ|g|)² / Σg²

    /// Whether it passes the gate at `level`: significant, and an effect worth naming that its
    /// fit determines (a θ the data do not move stays at its start, its error huge or undefined: a
    /// threshold on a wall the smoke never reaches sat at its start 0.35 ± 1e9 and was named on
    /// 1e-7 nats).
    bool passes(double level, const detail::CauseRow& row) const
    {
        return obs > 0 && gain > 0 && p < level && effect >= row.floor && std::isfinite(effect_se) &&
            effect_se < effect;
    }
};

Scored scoreCandidate(const Replay& r, const Models& m, Candidate c, const DiagnosisConfig& cfg)
{
    Scored s;
    s.block_gain.assign(size_t(r.blocks()), 0.0);
    for (int fold = 0; fold < 2; ++fold) {
        Candidate cf = c;
        const ReplayModel& base = m.fold[fold];
        s.fold_c[fold] = cf;
        if (c.cause == Cause::SectorDropout && !detail::findDropoutSector(r, base, fold, cf.from_rad, cf.to_rad))
            continue;
        s.fold_c[fold] = cf;
        const ThetaFit f = fitCandidate(r, base, cf, touched(r, cf, fold));
        s.fold_fit[fold] = f;
        if (!f.ok) continue;
        const detail::CandidateAt at(r, base, cf, J(f.theta, 0));
        for (const Obs& o : touched(r, cf, 1 - fold)) {
            const double gain = at.logLik(o).a - detail::modelLogLik(r, base, o);
            s.block_gain[size_t(r.scans[size_t(o.k)].block)] += gain;
            ++s.obs;
        }
    }
    double abs_sum = 0, sq_sum = 0;
    for (double g : s.block_gain) s.gain += g, abs_sum += std::abs(g), sq_sum += g * g;
    s.blocks_eff = sq_sum > 0 ? abs_sum * abs_sum / sq_sum : 0.0;
    const detail::CauseRow& row = detail::causeRow(c.cause);
    const detail::EffectScale scale = detail::effectScale(r, c);
    const auto effectOf = [&](double t) { return row.effect(t, scale); };
    double effect = 0, effect_se = 0;
    int fits = 0;
    for (const ThetaFit& f : s.fold_fit) {
        if (!f.ok) continue;
        effect += effectOf(f.theta);  // each fold's effect (a noise growth's θ may fit ±γ)
        // Its error propagated through the effect's slope at the fold's own θ (a difference over
        // ±se would cap it at |θ|; at the folds' mean θ, a fold at a width's or share's nil and
        // one with a width mixed e^θ of the one with the θ error of the other). The steeper
        // one-sided slope: an effect |θ| has slope 1 at θ ≈ 0 too, where a central difference
        // gives |θ|/h.
        const double h = 1e-4 * std::max(1.0, std::abs(f.theta)), e = effectOf(f.theta);
        const double slope = std::max(std::abs(effectOf(f.theta + h) - e), std::abs(e - effectOf(f.theta - h))) / h;
        effect_se += slope * f.se;
        ++fits;
    }
    if (fits > 0) {
        s.effect = effect / fits;
        s.effect_se = effect_se / (fits * M_SQRT2);  // on all the data: the folds' over √2
    }
    // Only a candidate that gains and is large enough to be named needs its p-value (the flips cost).
    // Not tested: NaN (reported as such, not as a p of 1).
    s.p = s.obs > 0 && s.gain > 0 && s.effect >= row.floor ? signFlipP(s.block_gain, cfg.sign_flips, cfg.seed) : NAN;
    s.c = c;
    return s;
}

/// The round's candidates: every cause, each surface for the per-surface ones.
std::vector<Candidate> candidates(const Replay& r, const ReplayModel& m, const DiagnosisConfig& cfg,
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
    if (r.from_saturation) add({Cause::ClockOffset});
    for (const auto& [s, n] : beams_on)
        if (n >= cfg.min_beams) add({Cause::SurfaceThreshold, s});
    add({Cause::ThresholdWidth});
    for (const auto& [s, n] : beams_on)
        if (n >= cfg.min_beams) add({Cause::SurfaceRangeBias, s});
    add({Cause::RangeNoiseGrowth});
    add({Cause::SmokeObstacleReturn});
    Candidate sector{Cause::SectorDropout};
    if (detail::findDropoutSector(r, m, -1, sector.from_rad, sector.to_rad)) add(sector);
    add({Cause::Hysteresis});
    return out;
}

/// An accepted candidate: its all-data fit, each fold's fit, the finding reported, and the level
/// it passed.
struct Accepted {
    Scored s;
    ThetaFit all;
    Finding f;
    double level = 0;

    /// Its θ into the models: the all-data fit, and each fold's own (a fold whose fit failed, or
    /// that found no sector, keeps its model: the all-data θ would carry the other fold's data).
    void commit(const Replay& r, Models& m) const
    {
        s.c.commit(r, all.theta, m.all);
        for (int fold = 0; fold < 2; ++fold)
            if (s.fold_fit[fold].ok) s.fold_c[fold].commit(r, s.fold_fit[fold].theta, m.fold[fold]);
    }
};

Accepted accept(const Replay& r, const Models& m, const Scored& s, double level)
{
    Accepted a;
    a.s = s;
    a.level = level;
    a.all = fitCandidate(r, m.all, s.c, touched(r, s.c, -1));
    if (a.all.ok && detail::causeRow(s.c.cause).jackknife) {
        const double se = detail::jackknifeSe(r, m.all, s.c, a.all.theta);
        if (std::isfinite(se) && !(a.all.se >= se)) a.all.se = se;  // also when the curvature gave none
    }
    a.f.cause = detail::causeName(s.c.cause);
    a.f.target = s.c.target(r);
    a.f.parameters = s.c.report(a.all.theta, a.all.se);
    if (s.c.cause == Cause::ClockOffset)  // reported as the clocks' whole difference, not the change
        a.f.parameters.front().second.value += m.all.ext.clock_offset_s;
    a.f.loglik_gain = s.gain;
    a.f.loglik_gain_per_beam = s.obs > 0 ? s.gain / double(s.obs) : 0.0;
    a.f.p_value = s.p;
    for (double g : s.block_gain) a.f.blocks += g != 0;
    return a;
}

/// The figures with model m_f predicting the scans of fold f (held out from its fit).
std::vector<ModelFigures> foldFigures(const Replay& r, const ReplayModel& m0, const ReplayModel& m1)
{
    std::map<std::string, ModelFigures> per;
    ModelFigures all;
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
            const ReplayModel& m = r.scans[k].block % 2 == 0 ? m0 : m1;
            const double ll = detail::modelLogLik(r, m, o);
            const detail::Prediction pred = detail::modelPrediction(r, m, o);
            const double p_err = pred.p_err, mu = pred.mean_m;
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
    std::vector<ModelFigures> out{all};
    for (auto& [name, f] : per) {
        finish(f, sse[name], rec[name]);
        out.push_back(f);
    }
    return out;
}

}  // namespace

std::vector<ModelFigures> modelFigures(const Replay& r, const ModelExtensions& m)
{
    const ReplayModel model(r, m);
    return foldFigures(r, model, model);
}

DiagnosisResult diagnose(const Replay& r, const DiagnosisConfig& cfg)
{
    DiagnosisResult res;
    res.blocks = r.blocks();
    res.shape = r.shape;
    res.shape_error_ln = r.shape_error_ln;
    if (res.blocks < 4)
        throw Error("diagnose",
                    "the run spans " + std::to_string(res.blocks) +
                        " time blocks; at least 4 are needed to hold some out (a longer run, or a shorter --block)");
    double max_density = 0;
    for (const auto& s : r.scans) max_density = std::max(max_density, s.density);
    if (!(max_density > 0)) throw Error("diagnose", "the run holds no smoke: nothing to diagnose");
    for (const auto& b : r.beams)
        if (b.surface >= 0) res.observations += (long long)r.scans.size();
    res.baseline = modelFigures(r, r.prior);
    Models models(r, r.prior);
    std::vector<Accepted> acc;
    for (int round = 1; round <= cfg.max_findings; ++round) {
        const std::vector<Candidate> cands = candidates(r, models.all, cfg, res.findings);
        if (cands.empty()) break;
        std::vector<Scored> scored;
        for (const Candidate& c : cands) {
            scored.push_back(scoreCandidate(r, models, c, cfg));
            if (cfg.progress) cfg.progress(round, int(scored.size()), int(cands.size()));
        }
        // Bonferroni in two families, α/2 each: the global causes (few) and the targeted ones (a
        // surface or a sector each), so that the many targets do not drown a global cause.
        int n_global = 0;
        for (const Candidate& c : cands) n_global += c.target(r).empty();
        const int n_targeted = int(cands.size()) - n_global;
        const Scored* best = nullptr;
        double best_level = 0;
        for (const Scored& s : scored) {
            const detail::CauseRow& row = detail::causeRow(s.c.cause);
            const bool global = s.c.target(r).empty();
            const double level = 0.5 * cfg.alpha / double(std::max(1, global ? n_global : n_targeted));
            res.tried.push_back(
                {round, row.name, s.c.target(r), s.gain, s.p, s.effect, s.effect_se, row.floor, s.blocks_eff, level});
            if (s.passes(level, row) && (!best || s.gain > best->gain)) {
                best = &s;
                best_level = level;
            }
        }
        if (!best) break;
        Accepted a = accept(r, models, *best, best_level);
        if (!a.all.ok) break;
        a.commit(r, models);
        res.findings.push_back(a.f);
        acc.push_back(a);
    }
    // Backward check and refit, each finding on top of all the others (Gauss–Seidel, up to four
    // passes): one that the others explain (a width absorbing a hysteresis found after it) no
    // longer gains on held-out data at the level it passed and is dropped; the rest take the value
    // fitted beside the others (a noise growth found before a range bias carried part of the bias).
    // After a drop the survivors are refitted again beside the ones left (a lone survivor too).
    for (int pass = 0; pass < 4 && acc.size() > 1; ++pass) {
        bool moved = false, dropped = false;
        for (size_t i = 0; i < acc.size();) {
            Models others(r, r.prior);
            for (size_t j = 0; j < acc.size(); ++j)
                if (j != i) acc[j].commit(r, others);
            const Scored s = scoreCandidate(r, others, acc[i].s.c, cfg);
            if (!s.passes(acc[i].level, detail::causeRow(s.c.cause))) {
                acc.erase(acc.begin() + long(i));
                moved = dropped = true;
                continue;
            }
            const Accepted a = accept(r, others, s, acc[i].level);
            if (a.all.ok) {  // a refit that fails keeps the value fitted before
                moved |= !(std::abs(a.all.theta - acc[i].all.theta) <= 0.1 * acc[i].all.se);
                acc[i] = a;
            }
            ++i;
        }
        if (dropped && acc.size() == 1) {  // fitted beside a finding now gone: once more alone
            const Models prior(r, r.prior);
            const Accepted a = accept(r, prior, scoreCandidate(r, prior, acc[0].s.c, cfg), acc[0].level);
            if (a.all.ok) acc[0] = a;
        }
        if (!moved) break;
    }
    models = Models(r, r.prior);
    res.findings.clear();
    for (const Accepted& a : acc) {
        a.commit(r, models);
        res.findings.push_back(a.f);
    }
    res.model = models.all.ext;
    // Held out: fold f's scans predicted by the model fitted on the other fold.
    res.extended = foldFigures(r, models.fold[1], models.fold[0]);
    for (const auto& f : res.findings)
        res.verdict += (res.verdict.empty() ? "" : ", ") + f.cause + (f.target.empty() ? "" : " (" + f.target + ")");
    if (res.verdict.empty()) res.verdict = "none";
    return res;
}

}  // namespace smokescan
