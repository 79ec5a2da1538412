#pragma once
// Internal: the candidate extensions of the diagnosis (docs/diagnosis.md) — how each one changes
// a beam's predictive terms, which observations it touches, its parameter and how it is reported.
#include <ceres/jet.h>

#include <string>
#include <vector>

#include "replay_model.hpp"
#include "smokescan/core/estimate.hpp"
#include "smokescan/core/quadrature.hpp"
#include "smokescan/diagnose/predictive.hpp"
#include "smokescan/diagnose/replay.hpp"

namespace smokescan::detail {

using J = ceres::Jet<double, 1>;

/// The causes, in the order they are tried (their names are a public interface). Each is one row
/// of the table in causes.cpp.
enum class Cause {
    ClockOffset,
    SurfaceThreshold,
    ThresholdWidth,
    SurfaceRangeBias,
    RangeNoiseGrowth,
    SmokeObstacleReturn,
    SectorDropout,
    Hysteresis
};
/// Every cause the diagnosis tries, in the order above.
inline constexpr Cause kCauses[] = {Cause::ClockOffset,      Cause::SurfaceThreshold, Cause::ThresholdWidth,
                                    Cause::SurfaceRangeBias, Cause::RangeNoiseGrowth, Cause::SmokeObstacleReturn,
                                    Cause::SectorDropout,    Cause::Hysteresis};
const char* causeName(Cause c);

/// One observation: scan k, beam b.
struct Obs {
    int k, b;
};

/// One candidate extension: a cause and its target, one parameter θ (0 or −∞ in θ's own
/// transform: today's model). What θ does is the cause's row of the table (causes.cpp).
struct Candidate {
    Cause cause = Cause::ThresholdWidth;
    int surface = -1;  ///< SurfaceThreshold, SurfaceRangeBias
    double from_rad = 0, to_rad = 0;  ///< SectorDropout

    /// @brief Starting values to try (the fit starts from the best): the likelihood of a range
    /// bias or an offset is flat far from its optimum, where the outlier share takes the readings.
    const std::vector<double>& starts() const;
    std::string target(const Replay& r) const;
    /// @brief Whether the candidate changes beam b's prediction at all.
    bool touches(const Replay& r, int b) const;
    /// @brief `model`'s extensions with θ committed (the model is left as it is).
    ModelExtensions with(const Replay& r, double theta, const ReplayModel& model) const;
    /// @brief θ into the extension model (the accepted finding).
    void commit(const Replay& r, double theta, ReplayModel& model) const;
    /// @brief Whether θ on top of `model` gives values the extensions can take (their bounds,
    /// shared with a sensor file's): a fit beyond them is refused, not reported.
    bool plausible(const Replay& r, double theta, const ReplayModel& model) const;
    /// @brief The reported parameters: θ and its standard error in the cause's own units.
    std::vector<std::pair<std::string, Estimate>> report(double theta, double se) const;
};

/// @brief The terms of today's model plus `model`'s extensions at observation o (no candidate).
template <class T>
BeamTerms<T> baseTerms(const Replay& r, const ReplayModel& model, const Obs& o);

/// @brief The stop probability and noise-free range of observation o's terms (after any
/// candidate's change): the paper model's Φ((ln C − ln P)/w) and L, or the physical model's
/// tables at the smoke's scale shifted by the threshold, averaged over the width (the normal's
/// quantiles, core/quadrature.hpp).
struct ObsMemo;
/// @param memo the observation's own between a fit's evaluations (J only; ObsMemo), or null
template <class T>
void finishTerms(const Replay& r, const Obs& o, BeamTerms<T>& x, ObsMemo* memo = nullptr);

/// What one observation's ln L keeps between a fit's evaluations: the values that did not move
/// with θ at the last one (an exact reuse: each is a pure function of inputs compared bit for
/// bit, so a fit gives the same doubles with and without it). Most candidates leave the column
/// and the reading's mean and variance alone, and ln C, the normal's exp and sqrt are most of a
/// beam's cost.
struct ObsMemo {
    double scale_column = NAN, ln_scale = NAN;  ///< ln C (physical: ln C/C_ref) at C [density·m]
    double column = NAN, ln_p = NAN, width = NAN;  ///< finishTerms' inputs at its last outputs:
    double stop = NAN, mu0_m = NAN, sd0_m = NAN;  ///< p_s, L and σ₀
    double mean_m = NAN, var_m2 = NAN, density = NAN;  ///< the reading's normal density at (mean, var)
};

struct ScanTerms;
struct CauseRow;

/// Candidate c at θ on top of a model: what its cause changes alike for a scan's beams is
/// computed once per scan when it is made, then each observation's ln L.
class CandidateAt {
public:
    /// @param r, model, c must outlive this.
    CandidateAt(const Replay& r, const ReplayModel& model, const Candidate& c, const J& theta);
    ~CandidateAt();
    /// @brief ln L of observation o; `memo`, when given, is o's own between calls (ObsMemo).
    J logLik(const Obs& o, ObsMemo* memo = nullptr) const;

private:
    const Replay& r_;
    const ReplayModel& m_;
    const Candidate& c_;
    const CauseRow& row_;  ///< c's row, found once
    J theta_;
    std::vector<ScanTerms> scans_;  ///< by scan, when the cause has shared terms
};
/// @brief ln L of observation o under `model` alone.
double modelLogLik(const Replay& r, const ReplayModel& model, const Obs& o);
/// What `model` predicts for one observation.
struct Prediction {
    double p_err;  ///< P(error value)
    double mean_m;  ///< the range's mean when it reads the surface [m]
    double sd_m;  ///< and its standard deviation [m]
};
/// @brief The prediction of observation o under `model`.
Prediction modelPrediction(const Replay& r, const ReplayModel& model, const Obs& o);

/// @brief The sector where beams fail in clear air more often than the model expects there:
/// over the scans where the smoke adds under 1 % to the model's clear-air errors (≥ 5 of them),
/// recorded errors exceeding the expected by 15 % of those scans; the longest run of such beams
/// with gaps of at most two, at least 2 beams and at most 60° wide, among the scans of `fold`
/// (−1: all). Returns false when there is none.
/// The widest sector a dropout is looked for in [rad].
constexpr double kMaxSector_rad = 60 * M_PI / 180;
bool findDropoutSector(const Replay& r, const ReplayModel& model, int fold, double& from_rad, double& to_rad);

}  // namespace smokescan::detail
