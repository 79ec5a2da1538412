// The table of the diagnosis's causes: each row is the whole of one cause (causes.hpp). The
// parameter θ is unbounded for the fit; each row maps it into its extension (a log for a width,
// a logistic for a share) and its bounds are ModelExtensions' (sensor_config/extensions.hpp).
#include "causes.hpp"

#include <cmath>

namespace smokescan::detail {
namespace {

double sigmoid(double z) { return 1 / (1 + std::exp(-z)); }
J sigmoid(const J& z) { return J(1.0) / (J(1.0) + exp(-z)); }

using Reported = std::vector<std::pair<std::string, Estimate>>;

/// A share reported from its logit θ: the logistic of θ, its error through the logistic's slope.
Reported share(const char* name, double theta, double se)
{
    const double p = sigmoid(theta);
    return {{name, {p, p * (1 - p) * se}}};
}

/// The surface's own extensions in `e`, made when missing.
SurfaceExtension& surfaceOf(const Replay& r, const Candidate& c, ModelExtensions& e)
{
    return e.surfaces[r.surface_names[size_t(c.surface)]];
}

/// A sector found on the replay's (unwrapped) beam angles, in degrees within the sensor file's
/// bounds: the same beams on the circle (SectorExtension::contains).
SectorExtension sectorOf(const Candidate& c, double dropout)
{
    double from = c.from_rad * 180 / M_PI, to = c.to_rad * 180 / M_PI;
    if (from < -360 || to > 360) {
        const double turns = std::floor(from / 360);
        from -= 360 * turns;
        to -= 360 * turns;
        if (to > 360) from -= 360, to -= 360;
    }
    return {from, to, dropout};
}

/// ln of a width or logit of a share below which it is nil (e^−16 ≈ 1e-7: under 1e-5 of the
/// floors of 0.05–0.1).
constexpr double kNilBelow = -16;

/// A share's logistic of θ, the same for every beam (ScanTerms::share).
void shareOfTheta(const Replay&, const ReplayModel&, size_t, const J& theta, ScanTerms& s) { s.share = sigmoid(theta); }

const CauseRow kRows[] = {
    {Cause::ClockOffset, "clock_offset", Target::Global,
     [] {  // the likelihood in an offset is rugged (one step per camera frame)
         std::vector<double> t;
         for (int i = -48; i <= 48; ++i) t.push_back(0.25 * i);
         return t;
     }(),
     [](const Replay& r, const ReplayModel&, const Candidate&, const Obs& o, const J&, const ScanTerms* s,
        BeamTerms<J>& x) {
         x.column = r.columnWith(size_t(o.k), size_t(o.b), s->density);
         x.width = s->width;
     },
     [](const Replay&, const Candidate&, double theta, ModelExtensions& e) { e.clock_offset_s += theta; },
     [](double theta, double se) {
         return Reported{{"offset_s", {theta, se}}};
     },
     "time_s", Shown::ErrorShare, [](double theta, const EffectScale&) { return std::abs(theta); }, 1.0, "|offset| [s]",
     true,
     [](const Replay& r, const ReplayModel& m, size_t k, const J& theta, ScanTerms& s) {
         // The density and its error read at the shifted time (the error piecewise linear in
         // time: its slope by a central difference).
         const double t = r.scans[k].time_s + m.offset_change_s, h = 1e-3;
         s.density = r.densityAt(J(t) + theta);
         const double sd = r.lnDensitySdAt(t + theta.a),
                      slope = (r.lnDensitySdAt(t + theta.a + h) - r.lnDensitySdAt(t + theta.a - h)) / (2 * h);
         const J e = J(sd) + (theta - J(theta.a)) * slope;  // sd, its derivative slope · dθ
         const double w = m.ext.threshold_width;
         s.width = sd > 0 || w > 0 ? sqrt(J(w * w) + e * e) : J(0.0);
     }},

    {Cause::SurfaceThreshold,
     "surface_threshold",
     Target::Surface,
     {-0.7, -0.35, 0, 0.35, 0.7},
     [](const Replay&, const ReplayModel&, const Candidate&, const Obs&, const J& theta, const ScanTerms*,
        BeamTerms<J>& x) { x.lnP += theta; },
     [](const Replay& r, const Candidate& c, double theta, ModelExtensions& e) {
         surfaceOf(r, c, e).threshold_factor += theta;
     },
     [](double theta, double se) {
         return Reported{{"ln_threshold_factor", {theta, se}},
                         {"threshold_factor", {std::exp(theta), std::exp(theta) * se}}};
     },
     "column",
     Shown::ErrorShare,
     [](double theta, const EffectScale&) { return std::abs(theta); },
     0.1,
     "|ln factor|"},

    {Cause::ThresholdWidth,
     "threshold_width",
     Target::Global,
     {std::log(0.05), std::log(0.1), std::log(0.2), std::log(0.4)},  // θ = ln w
     [](const Replay&, const ReplayModel&, const Candidate&, const Obs&, const J&, const ScanTerms* s,
        BeamTerms<J>& x) { x.width = s->width; },
     [](const Replay&, const Candidate&, double theta, ModelExtensions& e) { e.threshold_width = std::exp(theta); },
     [](double theta, double se) {
         return Reported{{"width_ln_column", {std::exp(theta), std::exp(theta) * se}}};
     },
     "column",
     Shown::ErrorShare,
     [](double theta, const EffectScale&) { return std::exp(theta); },
     0.08,
     "width [ln column]",
     false,
     [](const Replay&, const ReplayModel& m, size_t k, const J& theta, ScanTerms& s) {
         const J w = exp(theta);
         const double sd = m.ln_density_sd[k];
         s.width = sqrt(w * w + J(sd * sd));
     },
     kNilBelow},

    {Cause::SurfaceRangeBias,
     "surface_range_bias",
     Target::Surface,
     {-20, -10, -5, 0, 5, 10, 20, 40},
     [](const Replay&, const ReplayModel&, const Candidate&, const Obs&, const J& theta, const ScanTerms*,
        BeamTerms<J>& x) { x.beta += theta; },
     [](const Replay& r, const Candidate& c, double theta, ModelExtensions& e) {
         surfaceOf(r, c, e).range_bias += theta;
     },
     [](double theta, double se) {
         return Reported{{"bias_per_column_per_density_m", {theta, se}}};
     },
     "column",
     Shown::RangeMean,
     [](double theta, const EffectScale& e) { return std::abs(theta) * e.P * e.range_over_sd; },
     1.0,
     "|bias| at the column P [clear-air sd]"},

    {Cause::RangeNoiseGrowth,
     "range_noise_growth",
     Target::Global,
     {0.5, 2, 5, 10},
     [](const Replay&, const ReplayModel& m, const Candidate&, const Obs&, const J& theta, const ScanTerms*,
        BeamTerms<J>& x) {
         // γ enters squared: added in quadrature to the model's own (θ alone when it has none, so
         // that the derivative at θ = 0 stays finite).
         x.gamma = m.ext.range_noise_growth_m == 0 ? theta : sqrt(x.gamma * x.gamma + theta * theta);
     },
     [](const Replay&, const Candidate&, double theta, ModelExtensions& e) {
         e.range_noise_growth_m = std::hypot(e.range_noise_growth_m, theta);
     },
     [](double theta, double se) {
         return Reported{{"noise_growth_m_per_density_m", {std::abs(theta), se}}};
     },
     "column",
     Shown::RangeSpread,
     [](double theta, const EffectScale& e) { return std::abs(theta) * e.P * e.inv_sd; },
     0.5,
     "noise grown at the column P [clear-air sd]"},

    {Cause::SmokeObstacleReturn,
     "smoke_obstacle_return",
     Target::Global,
     {-4, -2, -1, 0},  // θ: logit of q
     [](const Replay&, const ReplayModel&, const Candidate&, const Obs&, const J&, const ScanTerms* s,
        BeamTerms<J>& x) { x.q = J(1.0) - (J(1.0) - x.q) * (J(1.0) - s->share); },
     [](const Replay&, const Candidate&, double theta, ModelExtensions& e) {
         e.smoke_obstacle_return = 1 - (1 - e.smoke_obstacle_return) * (1 - sigmoid(theta));
     },
     [](double theta, double se) { return share("short_return_share", theta, se); },
     "column",
     Shown::ErrorShare,
     [](double theta, const EffectScale&) { return sigmoid(theta); },
     0.05,
     "share",
     false,
     shareOfTheta,
     kNilBelow},

    {Cause::SectorDropout,
     "sector_dropout",
     Target::Sector,
     {-3, -1.5, 0, 1},  // θ: logit of d
     [](const Replay&, const ReplayModel&, const Candidate&, const Obs&, const J&, const ScanTerms* s,
        BeamTerms<J>& x) { x.d = J(1.0) - (J(1.0) - x.d) * (J(1.0) - s->share); },
     [](const Replay&, const Candidate& c, double theta, ModelExtensions& e) {
         e.sectors.push_back(sectorOf(c, sigmoid(theta)));
     },
     [](double theta, double se) { return share("dropout", theta, se); },
     "beam_angle_deg",
     Shown::ErrorShare,
     [](double theta, const EffectScale&) { return sigmoid(theta); },
     0.1,
     "dropout",
     false,
     shareOfTheta,
     kNilBelow},

    {Cause::Hysteresis,
     "hysteresis",
     Target::Global,
     {-0.8, -0.4, 0, 0.4, 0.8},  // θ = ln P(falling) − ln P(rising)
     [](const Replay& r, const ReplayModel&, const Candidate&, const Obs& o, const J& theta, const ScanTerms*,
        BeamTerms<J>& x) { x.lnP += (r.scans[size_t(o.k)].rising ? J(-0.5) : J(0.5)) * theta; },
     [](const Replay&, const Candidate&, double theta, ModelExtensions& e) { e.hysteresis += theta; },
     [](double theta, double se) {
         return Reported{{"ln_threshold_falling_over_rising", {theta, se}}};
     },
     "smoke_trend",
     Shown::ErrorShare,
     [](double theta, const EffectScale&) { return std::abs(theta); },
     0.1,
     "|h|"},
};

}  // namespace

EffectScale effectScale(const Replay& r, const Candidate& c)
{
    EffectScale e;
    e.P = r.config.paper.penetration_power;
    int n = 0;
    for (size_t b = 0; b < r.beams.size(); ++b) {
        if (!c.touches(r, int(b))) continue;
        const ReplayBeam& beam = r.beams[b];
        const double sd = r.isPhysical() ? r.physical.sd_clear[b]
            : beam.sigma_m > 0           ? beam.sigma_m
                                         : r.spec.rangeSigma(beam.range_m);
        if (!(sd > 0)) continue;
        e.range_over_sd += beam.range_m / sd;
        e.inv_sd += 1 / sd;
        ++n;
    }
    if (n > 0) e.range_over_sd /= n, e.inv_sd /= n;
    return e;
}

const CauseRow& causeRow(Cause c)
{
    for (const CauseRow& row : kRows)
        if (row.cause == c) return row;
    throw std::logic_error("a cause without a row in the table");
}

const CauseRow* causeRow(const std::string& name)
{
    for (const CauseRow& row : kRows)
        if (name == row.name) return &row;
    return nullptr;
}

const char* causeName(Cause c) { return causeRow(c).name; }

}  // namespace smokescan::detail
