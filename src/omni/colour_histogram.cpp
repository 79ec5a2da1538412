#include "smokescan/omni/colour_histogram.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <sstream>

#include "smokescan/core/error.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/io/text_input.hpp"

namespace smokescan {
namespace {
constexpr const char* kHeader = "# smokescan colour histogram v1, bins per channel:";
constexpr const char* kExposure = "# exposure ";
}  // namespace

ColourHistogram::ColourHistogram(int bins_per_channel) : bins_(bins_per_channel)
{
    if (bins_ < 1 || bins_ > 64) throw Error("colour histogram", "bins per channel must lie in 1…64");
    counts_.assign(size_t(bins_) * bins_ * bins_, 0);
}

int ColourHistogram::bin(float v) const
{
    if (!(v > 0)) return 0;  // also NaN
    return std::min(bins_ - 1, int(std::floor(double(v) * bins_)));
}

void ColourHistogram::add(float r, float g, float b)
{
    ++counts_[index(bin(r), bin(g), bin(b))];
    ++total_;
}

double ColourHistogram::share(float r, float g, float b) const
{
    return total_ ? double(counts_[index(bin(r), bin(g), bin(b))]) / double(total_) : 0.0;
}

uint64_t ColourHistogram::count(int r, int g, int b) const
{
    if (r < 0 || g < 0 || b < 0 || r >= bins_ || g >= bins_ || b >= bins_) return 0;
    return counts_[index(r, g, b)];
}

void ColourHistogram::setExposure(double scale)
{
    if (!(scale == 0 || (scale >= 1e-6 && scale <= 1e6)))
        throw Error("exposure", "must lie in [1e-6, 1e6] (0: unknown)");
    exposure_ = scale;
}

void ColourHistogram::save(const std::string& path) const
{
    AtomicFile f(path);
    std::ostream& o = f.stream();
    o << kHeader << " " << bins_ << "\n";
    if (exposure_ > 0) o << kExposure << std::setprecision(17) << exposure_ << "\n";
    for (int r = 0; r < bins_; ++r)
        for (int g = 0; g < bins_; ++g)
            for (int b = 0; b < bins_; ++b)
                if (const uint64_t c = counts_[index(r, g, b)]) o << r << " " << g << " " << b << " " << c << "\n";
    f.commit();
}

ColourHistogram ColourHistogram::load(const std::string& path)
{
    const std::string text = readTextInput(path, "colour histogram", size_t(16) << 20);
    std::istringstream in(text);
    std::string line;
    int lineno = 0;
    auto where = [&] { return path + ":" + std::to_string(lineno); };
    std::getline(in, line);
    ++lineno;
    const std::string head = kHeader;
    if (line.compare(0, head.size(), head) != 0) throw Error(where(), "not a smokescan colour histogram");
    std::istringstream hs(line.substr(head.size()));
    int bins = 0;
    std::string rest;
    if (!(hs >> bins) || (hs >> rest) || bins < 1 || bins > 64)
        throw Error(where(), "bins per channel must be an integer in 1…64");
    ColourHistogram h(bins);
    while (std::getline(in, line)) {
        ++lineno;
        if (line.compare(0, std::strlen(kExposure), kExposure) == 0) {
            std::istringstream es(line.substr(std::strlen(kExposure)));
            double x = 0;
            if (!(es >> x) || (es >> rest) || !(x >= 1e-6 && x <= 1e6))
                throw Error(where(), "exposure must be a number in [1e-6, 1e6]");
            if (h.exposure_ > 0) throw Error(where(), "exposure given twice");
            h.exposure_ = x;
            continue;
        }
        if (line.empty() || line[0] == '#') continue;
        std::istringstream ls(line);
        long long r, g, b, c;
        if (!(ls >> r >> g >> b >> c) || (ls >> rest)) throw Error(where(), "expected 'r g b count'");
        if (r < 0 || g < 0 || b < 0 || r >= bins || g >= bins || b >= bins)
            throw Error(where(), "bin outside the histogram's " + std::to_string(bins) + " per channel");
        if (c <= 0) throw Error(where(), "count must be a positive integer");
        uint64_t& slot = h.counts_[h.index(int(r), int(g), int(b))];
        if (slot) throw Error(where(), "bin given twice");
        slot = uint64_t(c);
        h.total_ += uint64_t(c);
    }
    if (h.total_ == 0) throw Error(path, "colour histogram has no counts");
    return h;
}

}  // namespace smokescan
