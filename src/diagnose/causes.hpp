#pragma once
// Internal: the table of the diagnosis's causes (docs/diagnosis.md), one row per cause: its name,
// what it targets, its parameter θ (the starts of its fit, how θ changes a beam's predictive
// terms, how it enters the model, its bounds through ModelExtensions', its reported values) and
// how the report shows it. A new cause is a row here and an entry in the Cause enum.
#include <string>
#include <utility>
#include <vector>

#include "candidates.hpp"

namespace smokescan::detail {

/// What a cause is tried on: the whole sensor, each surface, or the sector where beams fail.
enum class Target { Global, Surface, Sector };

/// The residual the report plots for a finding.
enum class Shown { ErrorShare, RangeMean, RangeSpread };

struct CauseRow {
    Cause cause;
    const char* name;  ///< the public name (diagnosis.json, report.md)
    Target target;
    std::vector<double> starts;  ///< values of θ the fit starts from (the best is taken)
    /// θ's change to one observation's terms (before finishTerms).
    void (*apply)(const Replay& r, const ReplayModel& m, const Candidate& c, const Obs& o, const J& theta,
                  BeamTerms<J>& x);
    /// θ into the extensions (the accepted finding).
    void (*commit)(const Replay& r, const Candidate& c, double theta, ModelExtensions& e);
    /// θ and its standard error as reported, in the cause's own units.
    std::vector<std::pair<std::string, Estimate>> (*report)(double theta, double se);
    const char* covariate;  ///< the report's covariate that shows the cause (residualsBy)
    Shown shown;
};

/// @brief The row of cause c.
const CauseRow& causeRow(Cause c);
/// @brief The row of the cause named `name`, or null.
const CauseRow* causeRow(const std::string& name);

}  // namespace smokescan::detail
