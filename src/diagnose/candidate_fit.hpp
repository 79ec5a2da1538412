#pragma once
// Internal: a candidate extension's maximum-likelihood fit (Ceres) on a set of observations.
#include <functional>
#include <vector>

#include "candidates.hpp"

namespace smokescan::detail {

/// A candidate's θ with its standard error (the larger of the observed information's and the
/// cluster-robust sandwich's over time blocks).
struct ThetaFit {
    bool ok = false;
    double theta = 0, se = NAN;
};

/// @brief The maximum-likelihood θ of candidate c on top of model m over `obs`, from the best
/// of its start values (or of `starts` when given; ranked on every 4th observation when there
/// are over 20,000, the three best of a rugged likelihood — a jackknife row's — ranked again on
/// all). A θ that walks below its row's nil_below (a width or share whose best is zero) ends the
/// fit there; when the lowest start is the best, the nil costs no more and the cost still falls
/// towards it there, the fit starts (and ends) at the nil.
ThetaFit fitCandidate(const Replay& r, const ReplayModel& m, const Candidate& c, const std::vector<Obs>& obs,
                      const std::vector<double>* starts = nullptr);

/// @brief The delete-a-group jackknife's standard error of θ over all the blocks: the blocks dealt
/// into `groups` groups (block mod groups), θ refitted without each. For a likelihood too rugged
/// for its curvature to mean anything (the clock offset's, stepped at each camera frame).
double jackknifeSe(const Replay& r, const ReplayModel& m, const Candidate& c, double theta, int groups = 8);

/// @brief The index of the start of least cost (a non-finite cost counts as +inf; ties: the first).
/// Up to 24 starts are all evaluated. A longer grid (the clock offset's 97, 0.25 s apart) is
/// searched coarse to fine: every other start and the last, then the starts beside the three best
/// coarse ones (all of them when none has a finite cost): 58 evaluations, not 97. A basin whose
/// coarse starts all cost more than three others' (narrower than about two steps, 0.5 s of clock
/// offset, and shallower there) is passed over.
size_t bestStart(const std::vector<double>& starts, const std::function<double(double)>& cost);

/// @brief The observations candidate c touches in fold `fold` (−1: all).
std::vector<Obs> touched(const Replay& r, const Candidate& c, int fold);

}  // namespace smokescan::detail
