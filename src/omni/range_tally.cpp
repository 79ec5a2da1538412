#include "smokescan/omni/range_tally.hpp"

#include <algorithm>
#include <cmath>

#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"

namespace smokescan {

ReadingOutcome classifyReading(double reading_m, double truth_m, double max_range_m, double tolerance_m)
{
    if (truth_m > max_range_m) {
        if (std::isnan(reading_m) || reading_m >= max_range_m - tolerance_m) return ReadingOutcome::Ok;
        return ReadingOutcome::Short;
    }
    if (std::isnan(reading_m)) return ReadingOutcome::None;
    if (reading_m < truth_m - tolerance_m) return ReadingOutcome::Short;
    if (reading_m > truth_m + tolerance_m) return ReadingOutcome::Long;
    return ReadingOutcome::Ok;
}

RangeTally::RangeTally(std::string sensor, double max_range_m, RangeTallyConfig cfg)
    : sensor_(std::move(sensor)), max_range_m_(max_range_m), cfg_(std::move(cfg))
{
    if (!(cfg_.tolerance_m > 0) || !std::isfinite(cfg_.tolerance_m))
        throw Error("tolerance_m", "must be positive and finite");
    if (!(max_range_m_ > 0) || !std::isfinite(max_range_m_)) throw Error("max_range_m", "must be positive and finite");
    const auto& e = cfg_.column_edges;
    if (e.size() < 2 || e.front() != 0 || !std::is_sorted(e.begin(), e.end()) ||
        std::adjacent_find(e.begin(), e.end()) != e.end())
        throw Error("column_edges", "must rise strictly from 0, at least two edges");
    bins_.resize(e.size() - 1);
}

void RangeTally::add(double column, double truth_m, double reading_m)
{
    const auto& e = cfg_.column_edges;
    if (!(column >= 0)) column = 0;
    const size_t b = std::min(size_t(std::upper_bound(e.begin(), e.end(), column) - e.begin()) - 1, bins_.size() - 1);
    RangeTallyBin& bin = bins_[b];
    ++bin.readings;
    switch (classifyReading(reading_m, truth_m, max_range_m_, cfg_.tolerance_m)) {
    case ReadingOutcome::Ok:
        ++bin.ok;
        break;
    case ReadingOutcome::Short:
        ++bin.shorter;
        break;
    case ReadingOutcome::Long:
        ++bin.longer;
        break;
    case ReadingOutcome::None:
        ++bin.none;
        break;
    }
    if (truth_m <= max_range_m_ && std::isfinite(reading_m)) {
        ++bin.ranged;
        bin.sum_abs_m += std::abs(reading_m - truth_m);
    }
}

RangeTallyBin RangeTally::total() const
{
    RangeTallyBin t;
    for (const RangeTallyBin& b : bins_) {
        t.readings += b.readings;
        t.ok += b.ok;
        t.shorter += b.shorter;
        t.longer += b.longer;
        t.none += b.none;
        t.ranged += b.ranged;
        t.sum_abs_m += b.sum_abs_m;
    }
    return t;
}

std::string RangeTally::table() const
{
    const auto line = [](const std::string& label, const RangeTallyBin& b) {
        const double n = double(std::max(1LL, b.readings));
        return fmt("  %-18s %7lld  %5.1f %%  (short %5.1f, long %5.1f, none %5.1f)  %7lld  ", label.c_str(), b.readings,
                   100 * b.failureRate(), 100 * double(b.shorter) / n, 100 * double(b.longer) / n,
                   100 * double(b.none) / n, b.ranged) +
            (b.ranged ? fmt("%.3f m\n", b.meanAbsM()) : std::string("-\n"));
    };
    std::string s = sensor_ + fmt(" (max range %.1f m, ok within %.2f m):\n", max_range_m_, cfg_.tolerance_m) +
        "  column [density.m]  readings  failed   by kind [%]                          ranges  mean |error|\n";
    const auto& e = cfg_.column_edges;
    for (size_t i = 0; i < bins_.size(); ++i)
        if (bins_[i].readings > 0)
            s += line(e[i + 1] > 1e299 ? fmt(">= %g", e[i]) : fmt("%g-%g", e[i], e[i + 1]), bins_[i]);
    return s + line("all", total());
}

}  // namespace smokescan
