#pragma once
/// @file scan_summary.hpp
/// @brief What a run of scans did, accumulated scan by scan (the scans need not be kept): the
/// error fraction on the beams that hit the target (surfaces whose names start with a prefix) and
/// the mean regional smoke column on them, per time bin; or, in a scene without a target, the error
/// fraction over all beams; where the beams cross smoke clouds (local smoke), the readings in the
/// clouds' cores and at their edges (cloud_profile.hpp). `smokescan scan` prints it.
#include <string>
#include <vector>

#include "smokescan/sensors/cloud_profile.hpp"
#include "smokescan/sensors/scanner.hpp"

namespace smokescan {

class ScanSummary {
public:
    /// @param target_prefix surfaces whose names start with it are the target
    /// @param bin_s time bin [s]; ≤ 0: about 36 bins over the run, a multiple of 5 s
    /// @param max_rows the table's most rows; more is an Error on --bin (0: no table is printed)
    ScanSummary(const Scene& scene, const Scanner& scanner, std::string target_prefix, double bin_s,
                const std::vector<double>& times, long long max_rows);

    /// @brief Accumulates one scan (with its beams kept).
    void add(const Scan& s);
    /// @brief The summary as text: a header line, the table per bin, the totals.
    std::string text();

private:
    void flushBin(double next_t0);

    const Scene& scene_;
    const Scanner& sc_;
    std::string target_;
    double first_t_, bin_ = 1, bin_t0_ = NAN, bin_col_ = 0;
    double first_err_ = NAN, last_err_ = NAN;
    std::vector<char> on_target_;
    int n_target_ = 0;
    long long scans_ = 0, all_errors_ = 0, all_beams_ = 0, errs_ = 0, total_ = 0, bin_err_ = 0, bin_n_ = 0,
              bin_rows_ = 0;
    std::string rows_;
    CloudProfile clouds_;
};

}  // namespace smokescan
