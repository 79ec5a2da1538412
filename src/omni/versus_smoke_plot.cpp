#include <algorithm>
#include <cmath>

#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/io/image.hpp"
#include "smokescan/omni/omni_plots.hpp"
#include "smokescan/plot/canvas.hpp"
#include "smokescan/plot/frame.hpp"
#include "smokescan/plot/palette.hpp"

namespace smokescan {
namespace {

/// One panel: `value(bin)` per sensor against the column bins first…last, categorical in x, where
/// `count(bin)` (the readings the value averages) is at least min_readings.
template <class Value, class Count>
void panel(Canvas& c, const Frame& f, const std::vector<RangeTally>& tallies, size_t first, size_t last,
           long long min_readings, Value value, Count count, const std::string& ylabel, const char* yfmt)
{
    c.line(f.x0, f.y1, f.x1, f.y1, {0, 0, 0});
    c.line(f.x0, f.y0, f.x0, f.y1, {0, 0, 0});
    for (int k = 0; k <= 4; ++k) {
        const double v = f.uy0 + (f.uy1 - f.uy0) * k / 4;
        c.line(f.x0 - 5, f.Y(v), f.x0, f.Y(v), {0, 0, 0});
        c.line(f.x0 + 1, f.Y(v), f.x1, f.Y(v), {0.9f, 0.9f, 0.9f});
        c.text(f.x0 - 52, f.Y(v) + 4, fmt(yfmt, v), 12);
    }
    c.text(f.x0, f.y0 - 8, ylabel, 13);
    const auto& edges = tallies.front().config().column_edges;
    for (size_t b = first; b <= last + 1; ++b) {
        const int x = f.X(double(b - first));
        c.line(x, f.y1, x, f.y1 + 5, {0, 0, 0});
        c.text(x - 14, f.y1 + 20, b + 1 < edges.size() ? fmt("%g", edges[b]) : std::string("inf"), 12);
    }
    for (size_t s = 0; s < tallies.size(); ++s) {
        const Col col = colourOf(tallies[s].sensor(), s);
        int px = -1, py = -1;
        for (size_t b = first; b <= last; ++b) {
            const RangeTallyBin& bin = tallies[s].bins()[b];
            if (count(bin) < min_readings) {
                px = -1;
                continue;
            }
            const int x = f.X(double(b - first) + 0.5), y = f.Y(value(bin));
            c.box(x - 3, y - 3, x + 3, y + 3, col, true);
            if (px >= 0) c.line(px, py, x, y, col);
            px = x, py = y;
        }
    }
}

}  // namespace

void writeVersusSmokePlot(const std::string& path, const std::vector<RangeTally>& tallies, const std::string& title,
                          long long min_readings)
{
    if (tallies.empty()) throw Error(path, "no sensors to plot");
    if (min_readings < 1) throw Error(path, "a bin needs at least one reading to be drawn");
    const size_t nb = tallies.front().bins().size();
    for (const RangeTally& t : tallies)
        if (t.config().column_edges != tallies.front().config().column_edges)
            throw Error(path, "the sensors' column bins differ");
    size_t first = nb, last = 0;
    double emax = 0.1;
    for (const RangeTally& t : tallies)
        for (size_t b = 0; b < nb; ++b)
            if (t.bins()[b].readings >= min_readings) {
                first = std::min(first, b), last = std::max(last, b);
                if (t.bins()[b].ranged >= min_readings) emax = std::max(emax, t.bins()[b].meanAbsM());
            }
    if (first > last) first = 0, last = nb - 1;
    emax = std::ceil(emax * 10) / 10;
    const int W = 820, H = 660, span = int(last - first + 1);
    Canvas c(W, H);
    c.text(80, 24, title, 15);
    const Frame top{80, 60, W - 190, 290, 0.0, double(span), 0.0, 100.0};
    const Frame bottom{80, 370, W - 190, 600, 0.0, double(span), 0.0, emax};
    const auto readings = [](const RangeTallyBin& b) { return b.readings; };
    const auto ranged = [](const RangeTallyBin& b) { return b.ranged; };
    panel(
        c, top, tallies, first, last, min_readings, [](const RangeTallyBin& b) { return 100 * b.failureRate(); },
        readings, "failed readings [%]", "%.0f");
    panel(
        c, bottom, tallies, first, last, min_readings, [](const RangeTallyBin& b) { return b.meanAbsM(); }, ranged,
        "mean |range error| of the ranges read [m]", "%.2f");
    c.text((bottom.x0 + bottom.x1) / 2 - 150, H - 18, "smoke column along the line of sight [density.m]", 13);
    // The key: as many sensors as the height holds, the rest counted (every sensor is in the
    // printed table); a name too long for the margin is shortened, marked with "...".
    const size_t rows = size_t((H - 80 - 60) / 22), keyed = tallies.size() <= rows ? tallies.size() : rows - 1;
    for (size_t s = 0; s < keyed; ++s) {
        const int y = 80 + 22 * int(s);
        const std::string& name = tallies[s].sensor();
        c.box(W - 170, y - 8, W - 156, y + 2, colourOf(name, s), true);
        std::string shown = name;
        if (name.size() > 19) {
            size_t cut = 16;  // on a character's first byte (UTF-8)
            while (cut > 0 && (static_cast<unsigned char>(name[cut]) & 0xC0) == 0x80) --cut;
            shown = name.substr(0, cut) + "...";
        }
        c.text(W - 148, y + 2, shown, 13);
    }
    int y = 80 + 22 * int(keyed);
    if (keyed < tallies.size())
        c.text(W - 170, (y += 22) - 20, fmt("+ %zu more (see the table)", tallies.size() - keyed), 11);
    c.text(W - 170, y + 10, fmt("bins with >= %lld", min_readings), 11);
    c.text(W - 170, y + 24, "readings (errors: ranges)", 11);
    writeImage(path, c.image());
}

}  // namespace smokescan
