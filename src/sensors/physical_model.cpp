#include "smokescan/sensors/physical_model.hpp"

#include <algorithm>
#include <cmath>
#include <complex>

#include "smokescan/core/error.hpp"
#include "smokescan/core/random.hpp"
#include "smokescan/sensor_config/lms200.hpp"
#include "smokescan/sensor_config/urg04lx.hpp"

namespace smokescan {
namespace {

constexpr double kC = 299792458.0;  // [m/s]
// The common random numbers of pulsedErrorProbability.
constexpr uint64_t kPredictiveSeed = 0x70726564;

}  // namespace

TauProfile::TauProfile(const std::vector<ProfileSegment>& s) : TauProfile(s, own_) {}

TauProfile::TauProfile(const std::vector<ProfileSegment>& s, std::vector<double>& storage) : seg_(s), cum_(storage)
{
    cum_.clear();
    cum_.reserve(seg_.size());
    double acc = 0;
    for (const auto& g : seg_) {
        cum_.push_back(acc);
        acc += g.density * (g.t1_m - g.t0_m);
    }
}

double TauProfile::tau(double r) const
{
    // first segment whose end lies beyond r
    auto it =
        std::upper_bound(seg_.begin(), seg_.end(), r, [](double v, const ProfileSegment& g) { return v < g.t1_m; });
    const size_t i = size_t(it - seg_.begin());
    if (i == seg_.size())
        return seg_.empty() ? 0.0 : cum_.back() + seg_.back().density * (seg_.back().t1_m - seg_.back().t0_m);
    return cum_[i] + seg_[i].density * std::max(0.0, r - seg_[i].t0_m);
}

double TauProfile::stretchEnd(double r) const
{
    auto it =
        std::upper_bound(seg_.begin(), seg_.end(), r, [](double v, const ProfileSegment& g) { return v < g.t1_m; });
    if (it == seg_.end()) return kInf;
    return it->t0_m <= r ? it->t1_m : it->t0_m;
}

double TauProfile::sigmaAt(double r) const
{
    auto it =
        std::upper_bound(seg_.begin(), seg_.end(), r, [](double v, const ProfileSegment& g) { return v < g.t1_m; });
    return (it != seg_.end() && it->t0_m <= r) ? it->density : 0.0;
}

double nirReflectance(const Material& m, double wl)
{
    return wl < 845 ? m.nir_785 : m.nir_905;  // the nearer of the two tabulated bands
}

double monostaticBrdf(const Material& m, double wl, double cos_theta)
{
    const double rho = nirReflectance(m, wl);
    double f = (1 - m.specular) * rho / M_PI;
    if (m.specular > 0 && cos_theta > 0) {
        // GGX with the half vector along the beam: θ_h = θ; Smith G1 twice; Schlick F = F0 = rho.
        const double a2 = std::pow(std::max(1e-3, m.roughness * m.roughness), 2);
        const double c2 = cos_theta * cos_theta, t2 = (1 - c2) / c2;
        const double D = a2 / (M_PI * c2 * c2 * (a2 + t2) * (a2 + t2));
        const double G1 = 2 / (1 + std::sqrt(1 + a2 * t2));
        f += m.specular * rho * D * G1 * G1 / (4 * c2);
    }
    return f;
}

double surfaceEchoPower(const PhysicalParams& p, const Material& m, double wl, double cos_theta, double R, double tau)
{
    if (!(R > 0) || cos_theta <= 0) return 0;
    const double T2 = tau == 0 ? 1.0 : std::exp(-2 * tau);  // most beams meet no smoke: no exp
    return M_PI * monostaticBrdf(m, wl, cos_theta) * cos_theta * p.overlap(R) / (R * R) * T2;
}

void appendSmokeEchoes(const PhysicalParams& p, const TauProfile& tau, const std::vector<ProfileSegment>& beta,
                       double s0, double s1, double offset, double gain, double lobe_ratio,
                       const std::vector<double>& blocked, EchoSource source, BeamSignal& out)
{
    const double n_sub = blocked.empty() ? 1.0 : double(blocked.size());
    for (const auto& g : beta) {
        const double a = std::max(g.t0_m, s0), b = std::min(g.t1_m, s1);
        if (!(b > a) || g.density <= 0) continue;
        const int nb = std::max(1, int(std::ceil((b - a) / p.smoke_bin_m)));
        const double dx = (b - a) / nb;
        // σ_t is constant on a β segment (both profiles come from the same voxels); τ advances
        // bin by bin and ∫exp(−2τ) over a bin is exact.
        const double sig = tau.sigmaAt(0.5 * (a + b));
        const double bin_T2 = sig * dx > 1e-9 ? -std::expm1(-2 * sig * dx) / (2 * sig) : dx;
        const double step_T2 = std::exp(-2 * sig * dx);
        double T2_0 = std::exp(-2 * tau.tau(a));
        for (int k = 0; k < nb; ++k, T2_0 *= step_T2) {
            const double xc = a + (k + 0.5) * dx, range = offset + xc;
            const double O = p.overlap(range);
            if (O <= 0) continue;
            double open = 1.0;  // share of the footprint still travelling at xc
            if (!blocked.empty())
                open = double(blocked.end() - std::upper_bound(blocked.begin(), blocked.end(), xc)) / n_sub;
            if (open <= 0) break;
            const double geom = 1.0 / (range * range + xc * xc * lobe_ratio);
            const double P = gain * open * M_PI * g.density * O * geom * T2_0 * bin_T2;
            if (P <= 0) continue;
            out.echoes.push_back({range, P, source});
            (source == EchoSource::Mirror ? out.mirror_power : out.smoke_power) += P;
        }
    }
}

namespace {

/// smokePiece's body, inlined into the smoke's points (about two a β segment).
inline SmokePiece pieceOf(double sigma_t, double len_m)
{
    const double h = 2 * sigma_t * len_m, len = len_m;
    if (h < 0.03) {
        // Their series in h (the terms left out below 1e-15 of the value): no exp, no division.
        const double step = 1 -
            h *
                (1 -
                 h * (1.0 / 2 - h * (1.0 / 6 - h * (1.0 / 24 - h * (1.0 / 120 - h * (1.0 / 720 - h * (1.0 / 5040)))))));
        const double integral = len *
            (1 - h * (1.0 / 2 - h * (1.0 / 6 - h * (1.0 / 24 - h * (1.0 / 120 - h * (1.0 / 720 - h * (1.0 / 5040)))))));
        const double centre = len * (0.5 - h * (1.0 / 12 - h * h * (1.0 / 720 - h * h * (1.0 / 30240))));
        return {step, integral, centre};
    }
    // By expm1: 1 − exp(−h) without its cancellation; the centre len·(1/h − 1/(eʰ − 1)) still
    // loses about 1/h ulps (a few 1e-15 at the switch).
    const double e = std::expm1(-h);  // exp(−h) − 1
    return {1 + e, -e / (2 * sigma_t), len * (1 / h + 1 / e + 1)};
}

}  // namespace

SmokePiece smokePiece(double sigma_t, double len_m) { return pieceOf(sigma_t, len_m); }

void depositSmokeCells(const PhysicalParams& p, const TauProfile& tau, const std::vector<ProfileSegment>& beta,
                       double s1, const std::vector<double>& blocked, BeamSignal& out)
{
    const double c = p.smoke_cell_m, inv_c = 1 / c;
    out.smoke_cell_m = c;
    if (beta.empty()) return;
    out.smoke_cells.assign(size_t(std::max(0.0, std::min(beta.back().t1_m, s1)) * inv_c) + 2, 0.0);
    // The sums kept in registers and written back at the end (stores to the points could
    // otherwise alias them).
    double* cells = out.smoke_cells.data();
    size_t first = out.smoke_cells.size();  // lowered to the first point given power
    double power = out.smoke_power;
    const double settled = p.overlapSettled_m(), O_settled = p.overlap(settled);
    const double n_sub = blocked.empty() ? 1.0 : double(blocked.size());
    auto blockedAfter = blocked.begin();  // the first sub-ray stop beyond the piece's start
    double open = 1.0;  // the share of the footprint still travelling there
    double last_end = -1, last_T2 = 1;  // where the last segment ended, and T² there
    auto sig_at = tau.segments().begin();
    const auto sig_end = tau.segments().end();
    // A whole piece between two points at the σ_t it was computed for (most segments have none).
    bool have_full = false;
    double full_sig = 0;
    SmokePiece full{};
    for (const auto& g : beta) {
        const double a = std::max(g.t0_m, 0.0), b = std::min(g.t1_m, s1);
        if (!(b > a) || g.density <= 0) continue;
        // A smoke segment usually starts where the last ended: T² carried on from there.
        double T2 = a == last_end ? last_T2 : std::exp(-2 * tau.tau(a));
        const double density_pi = M_PI * g.density;
        // The segment in stretches of constant σ_t (a volume that only absorbs may change σ_t
        // inside a β segment), so that over a piece [x, y]: ∫T² = T²(x)·(1 − exp(−2σ(y − x)))/(2σ).
        for (double sa = a; sa < b;) {
            // The σ_t segment holding sa (or the gap before the next), walked along with sa.
            while (sig_at != sig_end && sig_at->t1_m <= sa) ++sig_at;
            const bool inside = sig_at != sig_end && sig_at->t0_m <= sa;
            const double sb = std::min(b, sig_at == sig_end ? kInf : inside ? sig_at->t1_m : sig_at->t0_m);
            const double sig = inside ? sig_at->density : 0.0;
            long k = long(sa * inv_c);  // the piece lies between points k and k + 1
            if (double(k + 1) * c <= sa) ++k;
            for (double x = sa; x < sb;) {
                const double edge = double(k + 1) * c;
                double y = std::min(sb, edge);
                if (blockedAfter != blocked.end() && *blockedAfter <= x) {
                    while (blockedAfter != blocked.end() && *blockedAfter <= x) ++blockedAfter;
                    open = double(blocked.end() - blockedAfter) / n_sub;
                    if (open <= 0) {
                        out.smoke_first = first;
                        out.smoke_power = power;
                        return;
                    }
                }
                if (blockedAfter != blocked.end() && *blockedAfter < y) y = *blockedAfter;
                SmokePiece q;
                if (x == double(k) * c && y == edge) {
                    if (!have_full || full_sig != sig) {
                        full = pieceOf(sig, c);
                        full_sig = sig;
                        have_full = true;
                    }
                    q = full;
                } else {
                    q = pieceOf(sig, y - x);
                }
                // O(r)/r² at the centre of T², and the power shared from there between the
                // points around the piece, the nearer taking more (the centre kept).
                const double r = x + q.centre_m, O = r >= settled ? O_settled : p.overlap(r);
                const double P = open * density_pi * O / (r * r) * T2 * q.integral_m;
                if (P > 0) {
                    const double f = std::clamp(r * inv_c - double(k), 0.0, 1.0);
                    first = std::min(first, size_t(k));
                    cells[size_t(k)] += (1 - f) * P;
                    cells[size_t(k) + 1] += f * P;
                    power += P;
                }
                T2 *= q.step;
                if (y == edge) ++k;
                x = y;
            }
            sa = sb;
        }
        last_end = b;
        last_T2 = T2;
    }
    out.smoke_first = first;
    out.smoke_power = power;
}

namespace {

/// Phasors at both modulation frequencies: the starting values (the receiver's noise) plus the
/// summed echoes.
struct AmcwPhasors {
    std::complex<double> lo, hi;
    double k_lo = 0, k_hi = 0;  ///< 4π f / c [rad/m]
};

AmcwPhasors amcwPhasors(const PhysicalParams& p, const BeamSignal& s, std::complex<double> lo = {},
                        std::complex<double> hi = {})
{
    AmcwPhasors z{lo, hi, 4 * M_PI * p.mod_freq_lo_hz / kC, 4 * M_PI * p.mod_freq_hi_hz / kC};
    for (const Echo& e : s.echoes) {
        z.lo += std::polar(e.power, z.k_lo * e.range_m);
        z.hi += std::polar(e.power, z.k_hi * e.range_m);
    }
    return z;
}

/// The fine phase's range, unwrapped by the coarse one [m].
double amcwRange(const AmcwPhasors& z)
{
    const double L_hi = 2 * M_PI / z.k_hi;  // fine ambiguity interval [m]
    auto wrap = [](double phi) { return phi < 0 ? phi + 2 * M_PI : phi; };
    const double r_lo = wrap(std::arg(z.lo)) / z.k_lo, r_hi = wrap(std::arg(z.hi)) / z.k_hi;
    return r_hi + L_hi * std::round((r_lo - r_hi) / L_hi);
}

/// The URG's validity rules and phase unwrapping on measured phasors; ds_noise (a standard
/// normal) draws the datasheet noise added to the range.
BeamResult amcwRead(const LrfSpec& spec, const PhysicalParams& p, const BeamSignal& s, const AmcwPhasors& z,
                    double ds_noise)
{
    BeamResult r;
    auto fail = [&](long long code, const char* cause) { return markError(r, code, cause); };
    const double A_lo = std::abs(z.lo), A_hi = std::abs(z.hi);
    r.power = A_lo;
    if (A_lo > p.saturation_power) return fail(urg_code::kStrongReflection, "strong_reflection");
    if (A_lo < p.snr_min * p.noise_floor)
        return s.surface_in_range ? fail(urg_code::kLowIntensity, "low_intensity")
                                  : fail(urg_code::kNoReturn, "nothing_in_range");
    if (std::abs(A_hi - A_lo) > p.two_wave_tolerance * A_lo)
        return fail(urg_code::kTwoWaveDifference, "two_wave_difference");
    return reportRange(spec, amcwRange(z), ds_noise, r);
}

}  // namespace

BeamResult amcwBeam(const LrfSpec& spec, const PhysicalParams& p, const BeamSignal& s, KeyedRng& rng)
{
    // The receiver's noise is complex Gaussian on each phasor, drawn in this order: lo's imaginary
    // and real parts, then hi's (each in its own statement: as arguments of one call their order
    // was the compiler's; gcc's, right to left, kept).
    const double lo_im = rng.normal();
    const double lo_re = rng.normal();
    const double hi_im = rng.normal();
    const double hi_re = rng.normal();
    const std::complex<double> n_lo(p.noise_floor * lo_re, p.noise_floor * lo_im);
    const std::complex<double> n_hi(p.noise_floor * hi_re, p.noise_floor * hi_im);
    const AmcwPhasors z = amcwPhasors(p, s, n_lo, n_hi);
    const double ds_noise = rng.normal();
    return amcwRead(spec, p, s, z, ds_noise);
}

BeamResult amcwBeamExpected(const LrfSpec& spec, const PhysicalParams& p, const BeamSignal& s)
{
    return amcwRead(spec, p, s, amcwPhasors(p, s), 0.0);
}

AmcwAmplitudes amcwAmplitudes(const PhysicalParams& p, const BeamSignal& s)
{
    const AmcwPhasors z = amcwPhasors(p, s);
    return {std::abs(z.lo), std::abs(z.hi)};
}

double amcwErrorProbability(const PhysicalParams& p, const AmcwAmplitudes& A)
{
    const double sd = p.noise_floor;
    if (!(sd > 0))
        return (A.lo < 0 || A.lo > p.saturation_power || std::abs(A.hi - A.lo) > p.two_wave_tolerance * A.lo) ? 1.0
                                                                                                              : 0.0;
    const double mx = std::sqrt(A.lo * A.lo + sd * sd), my = std::sqrt(A.hi * A.hi + sd * sd);
    const double a = std::max(p.snr_min * sd, mx - 8 * sd), b = std::min(p.saturation_power, mx + 8 * sd);
    if (!(b > a)) return 1.0;
    // ∫ φ(x) P(|Y − x| ≤ t·x) dx over the valid X, midpoint rule: 32 points over at most 16σ
    // (the integrand is smooth on the scale of σ: half-σ steps are accurate to ~1e-6).
    auto Phi = [](double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); };
    const int n = 32;
    const double dx = (b - a) / n;
    double valid = 0;
    for (int k = 0; k < n; ++k) {
        const double x = a + (k + 0.5) * dx, z = (x - mx) / sd;
        const double pdf = std::exp(-0.5 * z * z) / (sd * std::sqrt(2 * M_PI));
        const double t = p.two_wave_tolerance * x;
        valid += pdf * (Phi((x + t - my) / sd) - Phi((x - t - my) / sd)) * dx;
    }
    return std::clamp(1.0 - valid, 0.0, 1.0);
}

double amcwRangeSigma(const LrfSpec& spec, const PhysicalParams& p, const BeamSignal& s)
{
    const AmcwPhasors z = amcwPhasors(p, s);
    const double ds = spec.rangeSigma(amcwRange(z)), A = std::abs(z.hi);
    const double phase = A > 0 ? p.noise_floor / (A * z.k_hi) : kInf;
    return std::sqrt(ds * ds + phase * phase);
}

double amcwErrorProbability(const LrfSpec& spec, const PhysicalParams& p, const BeamSignal& s)
{
    const AmcwPhasors z = amcwPhasors(p, s);
    const double p_rules = amcwErrorProbability(p, {std::abs(z.lo), std::abs(z.hi)});
    return 1 - (1 - p_rules) * (1 - reportErrorProbability(spec, amcwRange(z)));
}

namespace {

/// The smoke's points (q to a sample, point m at m·dr/q; 0 before first_cell) convolved with the
/// pulse onto the waveform: exp(−x²/2σ²) at whole multiples of the points' spacing, ± reach.
void addSmokeCells(Waveform& f, const std::vector<double>& cells, size_t first_cell, int q, double reach, int n)
{
    // kernel[r][t + K]: the weight of a point r points past sample j_c on sample j_c + t.
    const long K = long(std::ceil(reach / f.dr - 1e-9));
    const double cell_sig = f.dr / q / f.sig_p;
    // The same for every beam of a sensor: kept for each thread while the spacing stays.
    thread_local std::vector<double> kernel;
    thread_local double kernel_key[3] = {0, 0, 0};
    if (kernel_key[0] != q || kernel_key[1] != double(K) || kernel_key[2] != cell_sig) {
        kernel.assign(size_t(q) * size_t(2 * K + 1), 0.0);
        for (int r = 0; r < q; ++r)
            for (long t = -K; t <= K; ++t) {
                const double x = double(q * t - r) * cell_sig;
                kernel[size_t(r) * size_t(2 * K + 1) + size_t(t + K)] = std::exp(-0.5 * x * x);
            }
        kernel_key[0] = q;
        kernel_key[1] = double(K);
        kernel_key[2] = cell_sig;
    }
    const long first = std::lround(f.lo / f.dr);  // the waveform's first sample
    double* w = f.w.data();
    if (q == 2) {
        // Two points a sample (the lidars' grid): both onto the taps in one pass, each waveform
        // sample read and written once for the pair.
        const double* k0 = kernel.data() + K;
        const double* k1 = k0 + (2 * K + 1);
        for (size_t m = first_cell & ~size_t(1); m < cells.size(); m += 2) {
            const double P0 = m >= first_cell && cells[m] > 0 ? cells[m] : 0.0;  // (m + 1 may be the first)
            const double P1 = m + 1 < cells.size() && cells[m + 1] > 0 ? cells[m + 1] : 0.0;
            if (!(P0 > 0 || P1 > 0)) continue;
            const long jc = long(m) / 2;
            const long t0 = std::max(-K, first - jc), t1 = std::min(K, first + n - 1 - jc);
            if (t1 < t0) continue;  // points beyond the waveform's reach
            double* wc = w + (jc - first + t0);
            const double *c0 = k0 + t0, *c1 = k1 + t0;
            // Point m's term, then point m + 1's: the sums of one point at a time, in its order.
            for (long t = 0; t <= t1 - t0; ++t) wc[t] = (wc[t] + P0 * c0[t]) + P1 * c1[t];
        }
        return;
    }
    for (size_t m = first_cell; m < cells.size(); ++m) {  // the points before first_cell hold 0
        const double P = cells[m];
        if (!(P > 0)) continue;
        const long jc = long(m) / q, r = long(m) - q * jc;
        const double* kr = kernel.data() + size_t(r) * size_t(2 * K + 1) + K;
        const long t0 = std::max(-K, first - jc), t1 = std::min(K, first + n - 1 - jc);
        if (t1 < t0) continue;  // a point beyond the waveform's reach
        double* wc = w + (jc - first + t0);
        const double* kc = kr + t0;
        for (long t = 0; t <= t1 - t0; ++t) wc[t] += P * kc[t];
    }
}

}  // namespace

double pulseSigma_m(const PhysicalParams& p)
{
    return kC * p.pulse_fwhm_ns * 1e-9 / 2 / 2.354820045;  // FWHM in time → σ in range (half the path)
}

Waveform pulsedWaveform(double range_max_m, const PhysicalParams& p, const BeamSignal& s, int samples_per_sigma)
{
    Waveform f;
    pulsedWaveform(range_max_m, p, s, samples_per_sigma, f);
    return f;
}

void pulsedWaveform(double range_max_m, const PhysicalParams& p, const BeamSignal& s, int samples_per_sigma,
                    Waveform& f)
{
    f.lo = 0;
    f.w.clear();
    f.sig_p = pulseSigma_m(p);
    f.dr = f.sig_p / samples_per_sigma;
    const double reach = 4 * f.sig_p;
    const double r_end = range_max_m + reach;
    double lo = r_end, hi = 0;
    for (const Echo& e : s.echoes)
        if (e.power > 0 && e.range_m < r_end) {
            lo = std::min(lo, e.range_m - reach);
            hi = std::max(hi, e.range_m + reach);
        }
    // Smoke on points q to a sample (BeamSignal::smoke_cells): the grid starts on a point.
    const bool cells = !s.smoke_cells.empty();
    int q = 1;  // smoke points a sample
    if (cells) {
        q = int(std::lround(f.dr / s.smoke_cell_m));
        if (q < 1 || std::abs(q * s.smoke_cell_m - f.dr) > 1e-9 * f.dr)
            throw Error("pulsed waveform",
                        "smoke points every " + std::to_string(s.smoke_cell_m) + " m on a waveform sampled every " +
                            std::to_string(f.dr) + " m");
        // The first and last points with power within the window (points nearer than r_end form
        // a prefix): found from both ends, not by a pass over all of them.
        auto holds = [&](size_t k) { return s.smoke_cells[k] > 0 && double(k) * s.smoke_cell_m < r_end; };
        size_t k0 = s.smoke_first, k1 = s.smoke_cells.size();
        while (k0 < s.smoke_cells.size() && !holds(k0)) ++k0;
        const bool any = k0 < s.smoke_cells.size();
        if (any) {
            while (!holds(k1 - 1)) --k1;  // stops at k0 at the latest
            --k1;
            lo = std::min(lo, double(k0) * s.smoke_cell_m - reach);
            hi = std::max(hi, double(k1) * s.smoke_cell_m + reach);
        }
    }
    if (!(hi > lo)) return;
    f.lo = lo = cells ? std::max(0.0, std::floor(lo / f.dr)) * f.dr : std::max(0.0, lo);
    hi = std::min(hi, r_end);
    const int n = int(std::ceil((hi - lo) / f.dr)) + 1;
    f.w.assign(size_t(n), 0.0);
    if (cells) addSmokeCells(f, s.smoke_cells, s.smoke_first, q, reach, n);
    // Each echo's pulse exp(−x²/2σ²) on the grid by its recurrence: from one sample to the next
    // the value is multiplied by a ratio that itself shrinks by exp(−dr²/σ²) (two exps an echo).
    const double inv2s2 = 1.0 / (2 * f.sig_p * f.sig_p), shrink = std::exp(-2 * f.dr * f.dr * inv2s2);
    for (const Echo& e : s.echoes) {
        if (!(e.power > 0)) continue;
        const int k0 = std::max(0, int(std::floor((e.range_m - reach - lo) / f.dr)));
        const int k1 = std::min(n - 1, int(std::ceil((e.range_m + reach - lo) / f.dr)));
        const double x0 = lo + k0 * f.dr - e.range_m;
        double g = e.power * std::exp(-x0 * x0 * inv2s2), ratio = std::exp(-(2 * x0 * f.dr + f.dr * f.dr) * inv2s2);
        for (int k = k0; k <= k1; ++k) {
            f.w[size_t(k)] += g;
            g *= ratio;
            ratio *= shrink;
        }
    }
}

std::vector<WaveformEcho> waveformEchoes(const Waveform& f, double thr, int max_echoes)
{
    std::vector<WaveformEcho> out;
    const std::vector<double>& w = f.w;
    const int n = int(w.size());
    for (int k0 = 0; k0 < n && int(out.size()) < max_echoes;) {
        while (k0 < n && w[size_t(k0)] < thr) ++k0;
        if (k0 == n) break;
        int k1 = k0, kp = k0;
        double peak = w[size_t(k0)];
        while (k1 + 1 < n && w[size_t(k1 + 1)] >= thr) {
            ++k1;
            if (w[size_t(k1)] > peak) {
                peak = w[size_t(k1)];
                kp = k1;
            }
        }
        // Half-maximum crossings around the peak.
        out.push_back(waveformPeakAt(f, kp, 0.0, k0, n - 1));
        k0 = k1 + 1;
    }
    return out;
}

WaveformEcho waveformPeakAt(const Waveform& f, int kp, double pedestal, int from, int to)
{
    const std::vector<double>& w = f.w;
    WaveformEcho e;
    e.peak = w[size_t(kp)];
    e.peak_m = f.lo + kp * f.dr;
    const double half = pedestal + 0.5 * (e.peak - pedestal), lo = f.lo, dr = f.dr;
    int a = kp;
    while (a > from && w[size_t(a - 1)] >= half) --a;
    e.lead_m = lo + a * dr;
    if (a > 0 && w[size_t(a - 1)] < half) e.lead_m -= dr * (w[size_t(a)] - half) / (w[size_t(a)] - w[size_t(a - 1)]);
    int b = kp;
    while (b < to && w[size_t(b + 1)] >= half) ++b;
    e.trail_m = lo + b * dr;
    if (b < int(w.size()) - 1 && w[size_t(b + 1)] < half)
        e.trail_m += dr * (w[size_t(b)] - half) / (w[size_t(b)] - w[size_t(b + 1)]);
    return e;
}

namespace {

/// The LMS200's reading of a waveform (noise added in place when rng is given).
BeamResult pulsedRead(const LrfSpec& spec, const PhysicalParams& p, Waveform& f, KeyedRng* rng)
{
    BeamResult r;
    auto fail = [&](long long code, const char* cause) { return markError(r, code, cause); };
    if (f.w.empty()) return fail(spec.no_return_code, "no_echo");
    if (rng)
        for (double& v : f.w) v += p.noise_floor * rng->normal();
    const double ds_noise = rng ? rng->normal() : 0.0;
    const std::vector<WaveformEcho> found = waveformEchoes(f, p.threshold_snr * p.noise_floor, 1);
    if (found.empty()) return fail(spec.no_return_code, "no_echo");
    const WaveformEcho& e = found.front();
    r.power = e.peak;
    if (e.peak > p.saturation_power) return fail(lms_code::kDazzled, "dazzled");
    if (e.peak < p.valid_snr * p.noise_floor) return fail(lms_code::kWeakOrAmbiguous, "weak_echo");
    const double fwhm_pulse = 2.354820045 * f.sig_p;
    if (e.trail_m - e.lead_m > p.max_echo_width * fwhm_pulse) return fail(lms_code::kWeakOrAmbiguous, "ambiguous_echo");
    const double range = e.lead_m + 0.5 * fwhm_pulse;
    return reportRange(spec, range, ds_noise, r);
}

}  // namespace

BeamResult pulsedBeam(const LrfSpec& spec, const PhysicalParams& p, const BeamSignal& s, KeyedRng& rng)
{
    Waveform f = pulsedWaveform(spec.range_max_m, p, s);
    return pulsedRead(spec, p, f, &rng);
}

BeamResult pulsedBeamExpected(const LrfSpec& spec, const PhysicalParams& p, const BeamSignal& s)
{
    Waveform f = pulsedWaveform(spec.range_max_m, p, s);
    return pulsedRead(spec, p, f, nullptr);
}

double pulsedErrorProbability(const LrfSpec& spec, const PhysicalParams& p, const BeamSignal& s, int draws)
{
    const Waveform f = pulsedWaveform(spec.range_max_m, p, s);
    if (f.w.empty()) return 1.0;
    int errors = 0;
    for (int d = 0; d < draws; ++d) {
        KeyedRng rng(kPredictiveSeed, uint64_t(d), 0);
        Waveform g = f;
        errors += pulsedRead(spec, p, g, &rng).error;
    }
    return double(errors) / std::max(1, draws);
}

}  // namespace smokescan
