#pragma once
/// @file diagnosis.hpp
/// @brief Given a replayed run: what the simulation gets wrong, the cause, and the gain of the
/// extended model on data the fit did not see (docs/diagnosis.md).
///
/// The run's time blocks are dealt into two folds (even and odd blocks). A candidate extension is
/// fitted by maximum likelihood (Ceres) on one fold and scored on the other, both ways, so every
/// block has a held-out log-likelihood gain. Under "no such effect" a block's gain is as likely
/// negative as positive (a fit on other data can only hurt on average), so the exact sign-flip
/// test over the blocks' gains gives a p-value that holds whatever the blocks' correlation within.
/// A candidate is accepted when p < (alpha/2) / m, m the candidates of its family in the round —
/// the global causes, or the targeted ones (a surface or a sector each) — (Bonferroni over the
/// two families: at most `alpha` false alarms per round), the effect its folds fitted is at least
/// its cause's floor (the smallest effect worth naming, in the cause's own units: a 1 s clock
/// offset, a 10 % threshold shift, ..., docs/diagnosis.md §4; not a gain per beam, which would
/// depend on how many beams the room has), and its gain is the round's best; it then joins the
/// model and the search repeats (greedy), up to max_findings.
///
/// | field         | default | meaning                                                          |
/// |---------------|---------|------------------------------------------------------------------|
/// | alpha         | 0.05    | family-wise false-alarm level of each round                       |
/// | max_findings  | 4       | greedy rounds at most                                              |
/// | min_beams     | 3       | surfaces hit by fewer beams are not candidates' targets            |
/// | sign_flips    | 20000   | Monte Carlo sign flips when the blocks are too many to enumerate (> 20): p to ±3e-4 near the Bonferroni level |
/// | seed          | 1       | the sign-flip draws (results do not depend on threads)             |
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "smokescan/core/estimate.hpp"
#include "smokescan/diagnose/predictive.hpp"
#include "smokescan/diagnose/replay.hpp"

namespace smokescan {

struct DiagnosisConfig {
    /// Called after each candidate scored: the round, the candidates scored in it, their number.
    std::function<void(int round, int done, int total)> progress;
    double alpha = 0.05;
    int max_findings = 4;
    int min_beams = 3;
    long long sign_flips = 20000;
    uint64_t seed = 1;
};

/// Figures of a model on the run, per surface ("" = all). The baseline is fitted to nothing; the
/// extended model's figures are held out: each fold's scans predicted by the extensions fitted on
/// the other fold.
struct ModelFigures {
    std::string surface;
    long long beams = 0;  ///< observations (scan × beam)
    double loglik_per_beam = 0;  ///< mean log-likelihood of the recorded value
    double missed_error_rate = 0;  ///< recorded errors the model gave < 50 % (of recorded errors)
    double invented_error_rate = 0;  ///< recorded ranges the model gave ≥ 50 % error (of recorded ranges)
    double range_rmse_m = NAN;  ///< recorded − predicted range where both are ranges
};

/// One named cause.
struct Finding {
    std::string cause;  ///< clock_offset, surface_threshold, threshold_width, ...
    std::string target;  ///< surface name, "sector A..B deg", or "" (global)
    std::vector<std::pair<std::string, Estimate>> parameters;  ///< name (with unit) → value ± se
    double loglik_gain_per_beam = 0;  ///< held-out, over the observations it changes
    double loglik_gain = 0;  ///< held-out, total [nats]
    double p_value = 1;  ///< sign-flip test over the blocks
    int blocks = 0;  ///< blocks with a nonzero gain
};

/// A candidate tried in a round and not accepted, for the report.
struct Tried {
    int round = 0;
    std::string cause, target;
    double loglik_gain = 0;
    double p_value = NAN;  ///< NaN: not tested (no held-out gain, or the effect below its floor)
    double effect = 0;  ///< the effect its folds fitted, in its cause's own units (docs/diagnosis.md §4)
    double effect_se = NAN;  ///< its standard error
    double floor = 0;  ///< the cause's floor, in the same units
    double blocks = 0;  ///< the blocks its held-out gain is spread over, (Σ|g|)²/Σg²
    double level = 0;  ///< the level its p had to pass in its round
};

struct DiagnosisResult {
    std::vector<ModelFigures> baseline, extended;  ///< [0] = all surfaces, then per surface
    std::vector<Finding> findings;
    std::vector<Tried> tried;
    ModelExtensions model;  ///< the extended model (today's + the findings), as a sensor file keeps it
    std::string verdict;  ///< "none" or the causes found, comma separated
    int blocks = 0;
    long long observations = 0;
    SmokeShape shape = SmokeShape::Reference;  ///< where the replay put the camera's smoke
    double shape_error_ln = 0;  ///< the replay's Replay::shape_error_ln
};

/// @brief Diagnoses a replayed run. @throw Error when the run is too short to split into blocks
/// (fewer than 4) or holds no smoke at all.
DiagnosisResult diagnose(const Replay& replay, const DiagnosisConfig& cfg = {});

/// @brief The figures of a model on the run (in-sample), all surfaces then each.
std::vector<ModelFigures> modelFigures(const Replay& replay, const ModelExtensions& model);

}  // namespace smokescan
