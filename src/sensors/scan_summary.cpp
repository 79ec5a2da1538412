#include "smokescan/sensors/scan_summary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"

namespace smokescan {

ScanSummary::ScanSummary(const Scene& scene, const Scanner& sc, std::string target_prefix, double bin_s,
                         const std::vector<double>& times, long long max_rows)
    : scene_(scene), sc_(sc), target_(std::move(target_prefix)), first_t_(times.empty() ? 0.0 : times.front())
{
    const double span = times.empty() ? 0.0 : times.back() - times.front();
    bin_ = bin_s > 0 ? bin_s : std::max(1.0, std::ceil(span / 36.0 / 5.0) * 5.0);
    if (max_rows > 0 && span / bin_ + 1 > double(max_rows))
        throw Error("--bin",
                    "would print " + limits::count(std::floor(span / bin_) + 1) + " rows (at most " +
                        std::to_string(max_rows) + "; use a wider bin or --quiet)");
}

void ScanSummary::add(const Scan& s)
{
    ++scans_;
    clouds_.add(s);
    if (on_target_.empty()) {
        on_target_.assign(size_t(sc_.spec().n_beams), 0);
        for (size_t i = 0; i < on_target_.size() && i < s.beams.size(); ++i) {
            const int surf = s.beams[i].hit.surface;
            on_target_[i] = surf >= 0 && scene_.surfaces[size_t(surf)].name.rfind(target_, 0) == 0;
            n_target_ += on_target_[i];
        }
    }
    for (long long v : s.value) all_errors_ += sc_.spec().isErrorValue(v);
    all_beams_ += (long long)s.value.size();
    if (n_target_ == 0) return;
    const double t0 = first_t_ + bin_ * std::floor((s.time_s - first_t_) / bin_);
    if (bin_rows_ == 0 || t0 != bin_t0_) flushBin(t0);
    for (size_t i = 0; i < on_target_.size(); ++i) {
        if (!on_target_[i]) continue;
        const bool err = s.beams[i].error;
        bin_err_ += err;
        ++bin_n_;
        bin_col_ += s.beams[i].smoke.column_regional;
        if (err) {
            if (std::isnan(first_err_)) first_err_ = s.time_s;
            last_err_ = s.time_s;
        }
    }
}

std::string ScanSummary::text()
{
    std::string out;
    char line[512];
    std::snprintf(line, sizeof line, "sensor %s (%s, model %s): %lld scans, %d beams each, %d on '%s*'\n",
                  sc_.mount().name.c_str(), sensorTypeName(sc_.spec().type), sensorModelName(sc_.mount().config.model),
                  scans_, sc_.spec().n_beams, n_target_, target_.c_str());
    out += line;
    if (scans_ == 0) return out;
    if (clouds_.result().runs > 0) out += clouds_.result().text();
    if (n_target_ == 0) {  // no target in this scene: the error fraction over all beams
        std::snprintf(line, sizeof line, "error codes: %.1f %% of all beams\n",
                      100.0 * all_errors_ / std::max(1LL, all_beams_));
        return out + line;
    }
    flushBin(NAN);
    std::snprintf(line, sizeof line, "%10s %10s %22s %12s\n", "t0_s", "t1_s", "column_on_target_d.m", "error_frac");
    out += line + rows_;
    std::snprintf(line, sizeof line, "error codes on the target: %.1f %% of beams",
                  100.0 * errs_ / std::max(1LL, total_));
    out += line;
    if (!std::isnan(first_err_)) {
        std::snprintf(line, sizeof line, ", first at %.1f s, last at %.1f s", first_err_, last_err_);
        out += line;
    }
    return out + "\n";
}

void ScanSummary::flushBin(double next_t0)
{
    if (bin_rows_ > 0) {
        char row[96];
        std::snprintf(row, sizeof row, "%10.1f %10.1f %22.5f %12.3f\n", bin_t0_, bin_t0_ + bin_,
                      bin_n_ ? bin_col_ / bin_n_ : 0.0, bin_n_ ? double(bin_err_) / bin_n_ : 0.0);
        rows_ += row;
        errs_ += bin_err_;
        total_ += bin_n_;
    }
    bin_t0_ = next_t0;
    bin_err_ = bin_n_ = 0;
    bin_col_ = 0;
    ++bin_rows_;
}

}  // namespace smokescan
