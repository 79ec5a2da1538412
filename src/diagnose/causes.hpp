#pragma once
// Internal: the table of the diagnosis's causes (docs/diagnosis.md), one row per cause: its name,
// what it targets, its parameter θ (the starts of its fit, how θ changes a beam's predictive
// terms, how it enters the model, its bounds through ModelExtensions', its reported values) and
// how the report shows it. A new cause is a row here and an entry in the Cause enum.
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "candidates.hpp"

namespace smokescan::detail {

/// What a cause is tried on: the whole sensor, each surface, or the sector where beams fail.
enum class Target { Global, Surface, Sector };

/// The residual the report plots for a finding.
enum class Shown { ErrorShare, RangeMean, RangeSpread };

/// What a cause's effect is measured against: the column P a threshold or a column-scaled effect
/// is read at, and the clear reading's noise σ₀ of the beams the candidate changes.
struct EffectScale {
    double P = 0;  ///< the paper model's penetration power [density·m]
    double range_over_sd = 0;  ///< the mean of L/σ₀ over the beams the candidate changes
    double inv_sd = 0;  ///< the mean of 1/σ₀ over them [1/m]
};

/// What a cause's change shares among one scan's beams, computed once per scan at θ (CauseRow::scan).
struct ScanTerms {
    J density;  ///< the smoke's density [density]
    J width;  ///< the threshold's width in ln(column)
    J share;  ///< a share θ adds (short returns, dropout): its logistic, once, not per beam
};

struct CauseRow {
    Cause cause;
    const char* name;  ///< the public name (diagnosis.json, report.md)
    Target target;
    std::vector<double> starts;  ///< values of θ the fit starts from (the best is taken)
    /// θ's change to one observation's terms (before finishTerms).
    /// `s` is the observation's scan's ScanTerms when the row has `scan`, else null.
    void (*apply)(const Replay& r, const ReplayModel& m, const Candidate& c, const Obs& o, const J& theta,
                  const ScanTerms* s, BeamTerms<J>& x);
    /// θ into the extensions (the accepted finding).
    void (*commit)(const Replay& r, const Candidate& c, double theta, ModelExtensions& e);
    /// θ and its standard error as reported, in the cause's own units.
    std::vector<std::pair<std::string, Estimate>> (*report)(double theta, double se);
    const char* covariate;  ///< the report's covariate that shows the cause (residualsBy)
    Shown shown;
    /// The size of θ's effect, in the units of `floor`, on the replay's scale (EffectScale).
    double (*effect)(double theta, const EffectScale& scale);
    /// The smallest effect worth naming (practical significance, in the cause's own units, so
    /// that it does not depend on how many beams a room has): the replay's own small misfits
    /// (a lag of about 0.1–0.5 s from interpolating the camera's samples, a threshold a little
    /// sharper than the noise claims) are real and, over a quarter million beams, significant.
    double floor;
    const char* floor_unit;  ///< what `floor` measures, for the report and docs
    /// Its standard error from a jackknife over the blocks, not the likelihood's curvature (which
    /// a likelihood stepped at each camera frame makes meaningless).
    bool jackknife = false;
    /// What θ changes alike for all of scan k's beams (null: nothing shared), for `apply`.
    void (*scan)(const Replay& r, const ReplayModel& m, size_t k, const J& theta, ScanTerms& s) = nullptr;
    /// θ below which the extension is nil for every purpose (a log width or a logistic share at
    /// e^θ, under 1e-5 of its floor): a fit whose best is the boundary (no width, no share) walks
    /// θ towards −∞ with a vanishing gradient, and stops here instead (−∞: never); a fit whose
    /// lowest start is its best starts here when this is its optimum (fitCandidate).
    double nil_below = -INFINITY;
};

/// @brief The scale candidate c's effect is measured against on the replay (CauseRow::effect):
/// it does not depend on θ, so it is found once per candidate.
EffectScale effectScale(const Replay& r, const Candidate& c);

/// @brief The row of cause c.
const CauseRow& causeRow(Cause c);
/// @brief The row of the cause named `name`, or null.
const CauseRow* causeRow(const std::string& name);

}  // namespace smokescan::detail
