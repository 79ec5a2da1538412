#include "candidates.hpp"

#include <algorithm>
#include <cmath>

#include "causes.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"

namespace smokescan::detail {

template <class T>
BeamTerms<T> baseTerms(const Replay& r, const ReplayModel& m, const Obs& o)
{
    const ReplayBeam& beam = r.beams[size_t(o.b)];
    const ReplayScan& scan = r.scans[size_t(o.k)];
    const ModelExtensions& e = m.ext;
    BeamTerms<T> x;
    x.column = T(r.columnWith(size_t(o.k), size_t(o.b), m.density[size_t(o.k)]));
    const SurfaceExtension* own = beam.surface >= 0 ? &m.surface[size_t(beam.surface)] : nullptr;
    // The paper model's threshold is ln P; the physical model's is its own, shifted by 0.
    x.lnP = T(m.ln_p) + T(e.thresholdShift(own, scan.rising));
    x.width = T(m.width[size_t(o.k)]);
    x.beta = T(own ? own->range_bias : 0.0);
    x.gamma = T(e.range_noise_growth_m);
    x.q = T(e.smoke_obstacle_return);
    x.d = T(m.dropout[size_t(o.b)]);
    return x;
}
template BeamTerms<double> baseTerms<double>(const Replay&, const ReplayModel&, const Obs&);
template BeamTerms<J> baseTerms<J>(const Replay&, const ReplayModel&, const Obs&);

namespace {

/// A physical table's value at u = ln s: a cubic in u between grid points (Hermite, on the
/// table's tangents `slope`), linear in s from the clear value below the grid, the last value
/// above it.
template <class T>
T tableAt(const Replay::PhysicalTable& t, const std::vector<double>& v, const std::vector<double>& slope, double clear,
          size_t b, const T& u)
{
    using std::exp;
    const size_t G = size_t(t.grid);
    const double* row = v.data() + b * G;
    double ua;
    if constexpr (std::is_same_v<T, double>)
        ua = u;
    else
        ua = u.a;
    if (ua <= t.u_lo) return T(clear) + T(row[0] - clear) * exp(u - T(t.u_lo));
    const double x = (ua - t.u_lo) / t.du;
    if (x >= double(G - 1)) return T(row[G - 1]);
    const size_t j = size_t(x);
    const double* m = slope.data() + b * G;
    const T f = (u - T(t.u_lo + t.du * double(j))) / T(t.du), f2 = f * f, f3 = f2 * f;
    return T(row[j]) * (T(2.0) * f3 - T(3.0) * f2 + T(1.0)) + T(t.du * m[j]) * (f3 - T(2.0) * f2 + f) +
        T(row[j + 1]) * (T(3.0) * f2 - T(2.0) * f3) + T(t.du * m[j + 1]) * (f3 - f2);
}

template <class T>
double valueOf(const T& v)
{
    if constexpr (std::is_same_v<T, double>)
        return v;
    else
        return v.a;
}

/// Whether beam b's error table is constant (to 1e-12) over [u0, u1] on its grid (the clear value
/// below it counts when u0 lies below the grid).
bool flatBetween(const Replay::PhysicalTable& t, size_t b, double u0, double u1)
{
    const size_t G = size_t(t.grid);
    const auto cell = [&](double u) { return std::clamp(std::floor((u - t.u_lo) / t.du), -1.0, double(G - 1)); };
    const long j0 = long(cell(u0)), j1 = std::min(long(G) - 1, long(cell(u1)) + 1);
    // The table's flat stretches, found once (physicalTables): one lookup, not a walk over the cells.
    const int reach = j0 < 0 ? t.flat_reach_clear[b] : t.flat_reach[b * G + size_t(j0)];
    return reach >= j1;
}

/// Whether a Jet carries no derivative: θ did not move it.
bool still(const J& v) { return v.v[0] == 0; }

/// The reading's normal density at the recorded range; with a memo, reused while its mean and
/// variance stay.
J readingDensityOf(double recorded_m, const J& mean, const J& var, ObsMemo* memo)
{
    if (!memo || !still(mean) || !still(var)) return readingDensity(recorded_m, mean, var);
    if (mean.a != memo->mean_m || var.a != memo->var_m2)
        // a Jet's arithmetic, as without the memo (its division multiplies by the inverse)
        memo->mean_m = mean.a, memo->var_m2 = var.a, memo->density = readingDensity(recorded_m, mean, var).a;
    return J(memo->density);
}

/// ln(C / ref) (ref 1: ln C); with a memo, reused while C stays.
template <class T>
T lnScale(const T& column, double ref, ObsMemo* memo)
{
    using std::log;
    const auto ln = [&] { return ref == 1 ? log(column) : log(column / T(ref)); };
    if constexpr (std::is_same_v<T, J>) {
        if (memo && still(column)) {
            if (column.a != memo->scale_column) memo->scale_column = column.a, memo->ln_scale = ln().a;
            return J(memo->ln_scale);
        }
    }
    return ln();
}

/// finishTerms' work; `memo` for ln C alone.
template <class T>
void finish(const Replay& r, const Obs& o, BeamTerms<T>& x, ObsMemo* memo)
{
    const ReplayBeam& beam = r.beams[size_t(o.b)];
    if (!r.isPhysical()) {
        // extended::stopProbability, with ln C from the memo
        x.ps = x.column > T(0.0) ? extended::stopProbabilityLn(lnScale(x.column, 1, memo), x.lnP, x.width) : T(0.0);
        x.mu0 = T(beam.range_m);
        x.sd0 = T(beam.sigma_m > 0 ? beam.sigma_m : r.spec.rangeSigma(beam.range_m));
        return;
    }
    const Replay::PhysicalTable& t = r.physical;
    const size_t b = size_t(o.b);
    if (!(x.column > T(0.0)) || !(beam.column_ref > 0)) {
        x.ps = T(t.err_clear[b]);
        x.mu0 = T(t.range_clear[b]);
        x.sd0 = T(t.sd_clear[b]);
        return;
    }
    // The smoke's scale against the reference, with the threshold's shift: ln s − (ln P' − ln P).
    const T u = lnScale(x.column, beam.column_ref, memo) - x.lnP;
    const double* z = normalNodes();
    // Where the table is flat across the spread (clear air, dense smoke: most beams) the average
    // is its value; else the average over the normal's quantiles.
    if (flatBetween(t, b, valueOf(u + x.width * T(z[0])), valueOf(u + x.width * T(z[kNormalNodes - 1])))) {
        x.ps = tableAt(t, t.err, t.err_slope, t.err_clear[b], b, u);
    } else {
        x.ps = T(0.0);
        for (int i = 0; i < kNormalNodes; ++i)
            x.ps += tableAt(t, t.err, t.err_slope, t.err_clear[b], b, u + x.width * T(z[i]));
        x.ps /= T(double(kNormalNodes));
    }
    x.mu0 = tableAt(t, t.range, t.range_slope, t.range_clear[b], b, u);
    x.sd0 = tableAt(t, t.sd, t.sd_slope, t.sd_clear[b], b, u);
}

}  // namespace

template <class T>
void finishTerms(const Replay& r, const Obs& o, BeamTerms<T>& x, ObsMemo* memo)
{
    if constexpr (std::is_same_v<T, J>) {
        if (memo) {
            // p_s, L and σ₀ depend on the beam and on C, ln P and w alone: reused while those stay.
            ObsMemo& m = *memo;
            const bool fixed = still(x.column) && still(x.lnP) && still(x.width);
            if (fixed && x.column.a == m.column && x.lnP.a == m.ln_p && x.width.a == m.width) {
                x.ps = J(m.stop), x.mu0 = J(m.mu0_m), x.sd0 = J(m.sd0_m);
                return;
            }
            finish(r, o, x, memo);
            m.column = fixed ? x.column.a : NAN, m.ln_p = x.lnP.a, m.width = x.width.a;
            m.stop = x.ps.a, m.mu0_m = x.mu0.a, m.sd0_m = x.sd0.a;
            return;
        }
    }
    finish(r, o, x, nullptr);
}
template void finishTerms<double>(const Replay&, const Obs&, BeamTerms<double>&, ObsMemo*);
template void finishTerms<J>(const Replay&, const Obs&, BeamTerms<J>&, ObsMemo*);

const std::vector<double>& Candidate::starts() const { return causeRow(cause).starts; }

std::string Candidate::target(const Replay& r) const
{
    switch (causeRow(cause).target) {
    case Target::Surface:
        return r.surface_names[size_t(surface)];
    case Target::Sector:
        return fmt("sector %.1f..%.1f deg", from_rad * 180 / M_PI, to_rad * 180 / M_PI);
    case Target::Global:
        break;
    }
    return "";
}

bool Candidate::touches(const Replay& r, int b) const
{
    const ReplayBeam& beam = r.beams[size_t(b)];
    if (beam.surface < 0) return false;
    switch (causeRow(cause).target) {
    case Target::Surface:
        return beam.surface == surface;
    case Target::Sector:
        return beam.angle_rad >= from_rad && beam.angle_rad <= to_rad;
    case Target::Global:
        break;
    }
    return true;
}

ModelExtensions Candidate::with(const Replay& r, double theta, const ReplayModel& m) const
{
    ModelExtensions e = m.ext;
    causeRow(cause).commit(r, *this, theta, e);
    return e;
}

void Candidate::commit(const Replay& r, double theta, ReplayModel& m) const { m = ReplayModel(r, with(r, theta, m)); }

bool Candidate::plausible(const Replay& r, double theta, const ReplayModel& m) const
{
    return with(r, theta, m).withinBounds();
}

std::vector<std::pair<std::string, Estimate>> Candidate::report(double theta, double se) const
{
    return causeRow(cause).report(theta, se);
}

CandidateAt::CandidateAt(const Replay& r, const ReplayModel& m, const Candidate& c, const J& theta)
    : r_(r), m_(m), c_(c), row_(causeRow(c.cause)), theta_(theta)
{
    if (!row_.scan) return;
    scans_.resize(r.scans.size());
    for (size_t k = 0; k < r.scans.size(); ++k) row_.scan(r, m, k, theta, scans_[k]);
}

CandidateAt::~CandidateAt() = default;

J CandidateAt::logLik(const Obs& o, ObsMemo* memo) const
{
    BeamTerms<J> x = baseTerms<J>(r_, m_, o);
    row_.apply(r_, m_, c_, o, theta_, scans_.empty() ? nullptr : &scans_[size_t(o.k)], x);
    const ReplayBeam& beam = r_.beams[size_t(o.b)];
    const double recorded = double(r_.range_m[size_t(o.k)][size_t(o.b)]);
    finishTerms(r_, o, x, memo);
    // logLikelihood, with the reading's density from the memo
    if (std::isnan(recorded)) return logLikelihoodWith(x, recorded, beam.range_m, r_.spec.range_max_m, J(0.0));
    const J mean = extended::rangeMean(x.mu0, x.beta, x.column);
    const J var = extended::rangeVariance(x.sd0, x.gamma, x.column);
    return logLikelihoodWith(x, recorded, beam.range_m, r_.spec.range_max_m,
                             readingDensityOf(recorded, mean, var, memo));
}

double modelLogLik(const Replay& r, const ReplayModel& m, const Obs& o)
{
    const ReplayBeam& beam = r.beams[size_t(o.b)];
    BeamTerms<double> x = baseTerms<double>(r, m, o);
    finishTerms(r, o, x);
    return logLikelihood(x, double(r.range_m[size_t(o.k)][size_t(o.b)]), beam.range_m, r.spec.range_max_m);
}

namespace {

/// What a beam's finished terms predict.
Prediction predictionOf(const BeamTerms<double>& x)
{
    const double err = 0.5 * kLapse + (1 - kLapse) * extended::errorShare(x.d, x.ps, x.q);
    return {err, extended::rangeMean(x.mu0, x.beta, x.column),
            std::sqrt(extended::rangeVariance(x.sd0, x.gamma, x.column))};
}

}  // namespace

Prediction modelPrediction(const Replay& r, const ReplayModel& m, const Obs& o)
{
    BeamTerms<double> x = baseTerms<double>(r, m, o);
    finishTerms(r, o, x);
    return predictionOf(x);
}

bool findDropoutSector(const Replay& r, const ReplayModel& m, int fold, double& from_rad, double& to_rad)
{
    const size_t B = r.beams.size();
    // Per beam, over the scans where the smoke adds under 1 % to the errors the model expects in
    // clear air (whatever it expects there: the physical model's two-wave errors on a near wall),
    // the recorded errors and the expected ones.
    std::vector<int> clear(B, 0), errs(B, 0);
    std::vector<double> expected(B, 0.0);
    for (size_t k = 0; k < r.scans.size(); ++k) {
        if (fold >= 0 && r.scans[k].block % 2 != fold) continue;
        for (size_t b = 0; b < B; ++b) {
            if (r.beams[b].surface < 0) continue;
            const Obs o{int(k), int(b)};
            BeamTerms<double> x = baseTerms<double>(r, m, o);
            finishTerms(r, o, x);
            const double in_clear_air = r.isPhysical() ? r.physical.err_clear[b] : 0.0;
            if (x.ps > in_clear_air + 0.01) continue;  // the smoke makes errors here: not clear air
            ++clear[b];
            errs[b] += std::isnan(r.range_m[k][b]);
            expected[b] += predictionOf(x).p_err;
        }
    }
    size_t best0 = 0, best_n = 0;
    // Marked: recorded errors exceed the expected ones by 15 % of the clear scans (a dropout d
    // adds d·(1 − p) to a share p the model expects).
    auto marked = [&](size_t i) { return clear[i] >= 5 && double(errs[i]) - expected[i] > 0.15 * clear[i]; };
    for (size_t b = 0; b < B;) {
        if (!marked(b)) {
            ++b;
            continue;
        }
        // The run goes on over gaps of up to two beams that chance left below the mark.
        size_t e = b;
        while (true) {
            size_t next = e + 1;
            while (next < B && next <= e + 3 && !marked(next)) ++next;
            if (next < B && next <= e + 3 && marked(next))
                e = next;
            else
                break;
        }
        // A dirty window or an occluder is local: beams failing in clear air over more than 60°
        // are the smoke (or its measurement) misread, not a sector; the longest other run counts.
        const bool local = double(e - b + 1) * std::abs(r.spec.dangle_rad) <= kMaxSector_rad;
        if (local && e - b + 1 > best_n) {
            best_n = e - b + 1;
            best0 = b;
        }
        b = e + 1;
    }
    if (best_n < 2) return false;
    const double half = 0.5 * std::abs(r.spec.dangle_rad);
    const double a0 = r.beams[best0].angle_rad, a1 = r.beams[best0 + best_n - 1].angle_rad;
    from_rad = std::min(a0, a1) - half;
    to_rad = std::max(a0, a1) + half;
    return true;
}

}  // namespace smokescan::detail
