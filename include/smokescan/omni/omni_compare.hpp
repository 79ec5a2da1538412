#pragma once
/// @file omni_compare.hpp
/// @brief The omnicam's ranges against the laser's, scanline by scanline (the omnicam paper's
/// Table II): each valid laser point is placed on the scanline nearest its bearing from the
/// camera's vertical axis; where both read a range within the rangefinder's maximum, their
/// difference is counted, and differences beyond the outlier bound are left out and counted.
///
/// | parameter  | default | unit | meaning                                               |
/// |------------|---------|------|-------------------------------------------------------|
/// | outlier_m  | 1.25    | m    | the paper's: larger differences are left out           |
#include <vector>

#include "smokescan/omni/omni_run.hpp"

namespace smokescan {

/// @brief The laser's range seen from the camera's axis on each of the frame's scanlines: the
/// horizontal distance of the valid laser point nearest the scanline in bearing (NaN for none).
std::vector<double> laserPerScanline(const OmniFrame& f);

/// Running sums over compared scanlines.
struct OmniComparison {
    double outlier_m = 1.25;
    long long pairs = 0, outliers = 0;
    double sum_abs_m = 0, sum_pct = 0, sum_signed_m = 0;
    std::vector<double> differences_m;  ///< laser − omnicam, per compared scanline (the Fig. 9 histogram)

    /// @brief Adds one frame's scanlines.
    void add(const OmniFrame& f);
    double meanAbsM() const { return pairs ? sum_abs_m / double(pairs) : 0.0; }
    /// Mean of |laser − omnicam| / laser, in per cent.
    double meanPercent() const { return pairs ? sum_pct / double(pairs) : 0.0; }
    double meanSignedM() const { return pairs ? sum_signed_m / double(pairs) : 0.0; }
};

}  // namespace smokescan
