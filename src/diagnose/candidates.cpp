#include "candidates.hpp"

#include <algorithm>
#include <cmath>

#include "smokescan/core/format.hpp"

namespace smokescan::detail {
namespace {

double sigmoid(double z) { return 1 / (1 + std::exp(-z)); }
J sigmoid(const J& z) { return J(1.0) / (J(1.0) + exp(-z)); }

double sectorDropout(const Extensions& m, double angle)
{
    double keep = 1;
    // On the circle: a sector of the omnicam's may be given anywhere round it (300…360° or
    // −60…0°); a laser's sectors lie within its field, where this is the plain interval.
    for (const auto& s : m.sectors) {
        const double from_start = angle - s.from_rad - 2 * M_PI * std::floor((angle - s.from_rad) / (2 * M_PI));
        if (from_start <= s.to_rad - s.from_rad + 1e-12) keep *= 1 - s.dropout;
    }
    return 1 - keep;
}

template <class T>
T valueOr(const std::map<int, double>& m, int key)
{
    const auto it = m.find(key);
    return T(it == m.end() ? 0.0 : it->second);
}

}  // namespace

const char* causeName(Cause c)
{
    switch (c) {
    case Cause::ClockOffset:
        return "clock_offset";
    case Cause::SurfaceThreshold:
        return "surface_threshold";
    case Cause::ThresholdWidth:
        return "threshold_width";
    case Cause::SurfaceRangeBias:
        return "surface_range_bias";
    case Cause::RangeNoiseGrowth:
        return "range_noise_growth";
    case Cause::SmokeObstacleReturn:
        return "smoke_obstacle_return";
    case Cause::SectorDropout:
        return "sector_dropout";
    case Cause::Hysteresis:
        return "hysteresis";
    }
    return "?";
}

template <class T>
BeamTerms<T> baseTerms(const Replay& r, const Extensions& m, const Obs& o)
{
    const ReplayBeam& beam = r.beams[size_t(o.b)];
    const ReplayScan& scan = r.scans[size_t(o.k)];
    BeamTerms<T> x;
    if (r.from_saturation && m.clock_offset_s != 0)
        x.column = T(r.densityAt(scan.time_s + m.clock_offset_s) / r.density_ref * beam.column_ref);
    else
        x.column = T(r.columnAt(size_t(o.k), size_t(o.b)));
    // The paper model's threshold is ln P; the physical model's is its own, shifted by 0.
    x.lnP = T(r.isPhysical() ? 0.0 : std::log(r.config.paper.penetration_power)) +
        valueOr<T>(m.threshold_factor, beam.surface) + T(scan.rising ? -0.5 * m.hysteresis : 0.5 * m.hysteresis);
    x.width = T(std::hypot(m.width, scan.ln_density_sd));
    x.beta = valueOr<T>(m.range_bias, beam.surface);
    x.gamma = T(m.noise_growth_m);
    x.q = T(m.obstacle_return);
    x.d = T(sectorDropout(m, beam.angle_rad));
    return x;
}
template BeamTerms<double> baseTerms<double>(const Replay&, const Extensions&, const Obs&);
template BeamTerms<J> baseTerms<J>(const Replay&, const Extensions&, const Obs&);

namespace {

/// A physical table's value at u = ln s: linear in u on the grid, linear in s from the clear
/// value below it, the last value above it.
template <class T>
T tableAt(const Replay::PhysicalTable& t, const std::vector<double>& v, double clear, size_t b, const T& u)
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
    const T f = (u - T(t.u_lo + t.du * double(j))) / T(t.du);
    return T(row[j]) + T(row[j + 1] - row[j]) * f;
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
    const double* row = t.err.data() + b * G;
    const auto cell = [&](double u) { return std::clamp(std::floor((u - t.u_lo) / t.du), -1.0, double(G - 1)); };
    const long j0 = long(cell(u0)), j1 = long(cell(u1)) + 1;
    double lo = j0 < 0 ? t.err_clear[b] : row[j0], hi = lo;
    for (long j = std::max(0L, j0); j <= std::min(long(G) - 1, j1); ++j) {
        lo = std::min(lo, row[j]);
        hi = std::max(hi, row[j]);
    }
    return hi - lo < 1e-12;
}

}  // namespace

template <class T>
void finishTerms(const Replay& r, const Obs& o, BeamTerms<T>& x)
{
    using std::erfc;
    using std::log;
    const ReplayBeam& beam = r.beams[size_t(o.b)];
    if (!r.isPhysical()) {
        x.ps = x.column > T(0.0) ? T(0.5) * erfc(-(log(x.column) - x.lnP) / x.width / T(M_SQRT2)) : T(0.0);
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
    const T u = log(x.column / T(beam.column_ref)) - x.lnP;
    const double* z = normalNodes();
    // Where the table is flat across the spread (clear air, dense smoke: most beams) the average
    // is its value; else the average over the normal's quantiles.
    if (flatBetween(t, b, valueOf(u + x.width * T(z[0])), valueOf(u + x.width * T(z[kNormalNodes - 1])))) {
        x.ps = tableAt(t, t.err, t.err_clear[b], b, u);
    } else {
        x.ps = T(0.0);
        for (int i = 0; i < kNormalNodes; ++i) x.ps += tableAt(t, t.err, t.err_clear[b], b, u + x.width * T(z[i]));
        x.ps /= T(double(kNormalNodes));
    }
    x.mu0 = tableAt(t, t.range, t.range_clear[b], b, u);
    x.sd0 = tableAt(t, t.sd, t.sd_clear[b], b, u);
}
template void finishTerms<double>(const Replay&, const Obs&, BeamTerms<double>&);
template void finishTerms<J>(const Replay&, const Obs&, BeamTerms<J>&);

std::vector<double> Candidate::starts() const
{
    switch (cause) {
    case Cause::ClockOffset: {  // the likelihood in an offset is rugged (one step per camera frame)
        std::vector<double> t;
        for (int i = -48; i <= 48; ++i) t.push_back(0.25 * i);
        return t;
    }
    case Cause::SurfaceThreshold:
        return {-0.7, -0.35, 0, 0.35, 0.7};
    case Cause::ThresholdWidth:
        return {std::log(0.05), std::log(0.1), std::log(0.2), std::log(0.4)};
    case Cause::SurfaceRangeBias:
        return {-20, -10, -5, 0, 5, 10, 20, 40};
    case Cause::RangeNoiseGrowth:
        return {0.5, 2, 5, 10};
    case Cause::SmokeObstacleReturn:
        return {-4, -2, -1, 0};
    case Cause::SectorDropout:
        return {-3, -1.5, 0, 1};
    case Cause::Hysteresis:
        return {-0.8, -0.4, 0, 0.4, 0.8};
    }
    return {theta_start};
}

std::string Candidate::target(const Replay& r) const
{
    switch (cause) {
    case Cause::SurfaceThreshold:
    case Cause::SurfaceRangeBias:
        return r.surface_names[size_t(surface)];
    case Cause::SectorDropout:
        return fmt("sector %.1f..%.1f deg", from_rad * 180 / M_PI, to_rad * 180 / M_PI);
    default:
        return "";
    }
}

bool Candidate::touches(const Replay& r, int b) const
{
    const ReplayBeam& beam = r.beams[size_t(b)];
    if (beam.surface < 0) return false;
    switch (cause) {
    case Cause::SurfaceThreshold:
    case Cause::SurfaceRangeBias:
        return beam.surface == surface;
    case Cause::SectorDropout:
        return beam.angle_rad >= from_rad && beam.angle_rad <= to_rad;
    default:
        return true;
    }
}

void Candidate::apply(const Replay& r, const Extensions& m, const Obs& o, const J& theta, BeamTerms<J>& x) const
{
    const ReplayBeam& beam = r.beams[size_t(o.b)];
    const ReplayScan& scan = r.scans[size_t(o.k)];
    switch (cause) {
    case Cause::ClockOffset:
        x.column = r.densityAt(J(scan.time_s + m.clock_offset_s) + theta) / J(r.density_ref) * J(beam.column_ref);
        break;
    case Cause::SurfaceThreshold:
        x.lnP += theta;
        break;
    case Cause::ThresholdWidth: {
        const J w = exp(theta);
        x.width = sqrt(w * w + J(scan.ln_density_sd * scan.ln_density_sd));
        break;
    }
    case Cause::SurfaceRangeBias:
        x.beta += theta;
        break;
    case Cause::RangeNoiseGrowth:
        // γ enters squared: added in quadrature to the model's own (θ alone when it has none, so
        // that the derivative at θ = 0 stays finite).
        x.gamma = m.noise_growth_m == 0 ? theta : sqrt(x.gamma * x.gamma + theta * theta);
        break;
    case Cause::SmokeObstacleReturn:
        x.q = J(1.0) - (J(1.0) - x.q) * (J(1.0) - sigmoid(theta));
        break;
    case Cause::SectorDropout:
        x.d = J(1.0) - (J(1.0) - x.d) * (J(1.0) - sigmoid(theta));
        break;
    case Cause::Hysteresis:
        x.lnP += (scan.rising ? J(-0.5) : J(0.5)) * theta;
        break;
    }
}

void Candidate::commit(double theta, Extensions& m) const
{
    switch (cause) {
    case Cause::ClockOffset:
        m.clock_offset_s += theta;
        break;
    case Cause::SurfaceThreshold:
        m.threshold_factor[surface] += theta;
        break;
    case Cause::ThresholdWidth:
        m.width = std::exp(theta);
        break;
    case Cause::SurfaceRangeBias:
        m.range_bias[surface] += theta;
        break;
    case Cause::RangeNoiseGrowth:
        m.noise_growth_m = std::hypot(m.noise_growth_m, theta);
        break;
    case Cause::SmokeObstacleReturn:
        m.obstacle_return = 1 - (1 - m.obstacle_return) * (1 - sigmoid(theta));
        break;
    case Cause::SectorDropout:
        m.sectors.push_back({from_rad, to_rad, sigmoid(theta)});
        break;
    case Cause::Hysteresis:
        m.hysteresis += theta;
        break;
    }
}

std::vector<std::pair<std::string, Estimate>> Candidate::report(double theta, double se) const
{
    switch (cause) {
    case Cause::ClockOffset:
        return {{"offset_s", {theta, se}}};
    case Cause::SurfaceThreshold:
        return {{"ln_threshold_factor", {theta, se}}, {"threshold_factor", {std::exp(theta), std::exp(theta) * se}}};
    case Cause::ThresholdWidth:
        return {{"width_ln_column", {std::exp(theta), std::exp(theta) * se}}};
    case Cause::SurfaceRangeBias:
        return {{"bias_per_column_per_density_m", {theta, se}}};
    case Cause::RangeNoiseGrowth:
        return {{"noise_growth_m_per_density_m", {std::abs(theta), se}}};
    case Cause::SmokeObstacleReturn:
    case Cause::SectorDropout: {
        const double p = sigmoid(theta);
        return {{cause == Cause::SectorDropout ? "dropout" : "short_return_share", {p, p * (1 - p) * se}}};
    }
    case Cause::Hysteresis:
        return {{"ln_threshold_falling_over_rising", {theta, se}}};
    }
    return {};
}

J candidateLogLik(const Replay& r, const Extensions& m, const Candidate& c, const Obs& o, const J& theta)
{
    BeamTerms<J> x = baseTerms<J>(r, m, o);
    c.apply(r, m, o, theta, x);
    finishTerms(r, o, x);
    const ReplayBeam& beam = r.beams[size_t(o.b)];
    return logLikelihood(x, double(r.range_m[size_t(o.k)][size_t(o.b)]), beam.range_m, r.spec.range_max_m);
}

double modelLogLik(const Replay& r, const Extensions& m, const Obs& o)
{
    const ReplayBeam& beam = r.beams[size_t(o.b)];
    BeamTerms<double> x = baseTerms<double>(r, m, o);
    finishTerms(r, o, x);
    return logLikelihood(x, double(r.range_m[size_t(o.k)][size_t(o.b)]), beam.range_m, r.spec.range_max_m);
}

Prediction modelPrediction(const Replay& r, const Extensions& m, const Obs& o)
{
    BeamTerms<double> x = baseTerms<double>(r, m, o);
    finishTerms(r, o, x);
    const double err = 0.5 * kLapse + (1 - kLapse) * (x.d + (1 - x.d) * x.ps * (1 - x.q));
    return {err, x.mu0 * (1 + x.beta * x.column), std::sqrt(x.sd0 * x.sd0 + x.gamma * x.gamma * x.column * x.column)};
}

bool findDropoutSector(const Replay& r, const Extensions& m, int fold, double& from_rad, double& to_rad)
{
    const size_t B = r.beams.size();
    std::vector<int> clear(B, 0), errs(B, 0);
    for (size_t k = 0; k < r.scans.size(); ++k) {
        if (fold >= 0 && r.scans[k].block % 2 != fold) continue;
        for (size_t b = 0; b < B; ++b) {
            if (r.beams[b].surface < 0) continue;
            const double p_err = modelPrediction(r, m, {int(k), int(b)}).p_err;
            if (p_err > 0.01) continue;  // the model expects errors here: not clear air
            ++clear[b];
            errs[b] += std::isnan(r.range_m[k][b]);
        }
    }
    size_t best0 = 0, best_n = 0;
    auto marked = [&](size_t i) { return clear[i] >= 5 && errs[i] > 0.15 * clear[i]; };
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

bool Candidate::plausible(double theta, const Extensions& m) const
{
    // The model's value once θ is committed, within a sensor file's bounds (sensor_tables.cpp).
    switch (cause) {
    case Cause::ClockOffset:
        return std::abs(m.clock_offset_s + theta) <= 60;
    case Cause::SurfaceThreshold:
        return std::abs(valueOr<double>(m.threshold_factor, surface) + theta) <= 5;
    case Cause::Hysteresis:
        return std::abs(m.hysteresis + theta) <= 5;
    case Cause::ThresholdWidth:
        return theta <= std::log(5.0);
    case Cause::SurfaceRangeBias:
        return std::abs(valueOr<double>(m.range_bias, surface) + theta) <= 1e4;
    case Cause::RangeNoiseGrowth:
        return std::hypot(m.noise_growth_m, theta) <= 1e3;
    case Cause::SmokeObstacleReturn:
    case Cause::SectorDropout:
        return true;
    }
    return false;
}

}  // namespace smokescan::detail
