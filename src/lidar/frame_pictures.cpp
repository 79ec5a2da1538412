#include "smokescan/lidar/frame_pictures.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "smokescan/core/error.hpp"

namespace smokescan {
namespace {

void put(Image& im, int x, int y, float r, float g, float b)
{
    if (x < 0 || y < 0 || x >= im.width || y >= im.height) return;
    im.at(x, y, 0) = r;
    im.at(x, y, 1) = g;
    im.at(x, y, 2) = b;
}

}  // namespace

Image rangeImage(const LidarFrame& f, const LidarSpec& spec, double range_max_m)
{
    if (spec.pattern != PatternKind::Spinning || f.channels < 1 || f.columns < 1)
        throw Error("range image", "the " + spec.name + "'s frames have no channels × columns to draw");
    // Rows by elevation, highest first (a Velodyne fires its channels interleaved).
    std::vector<int> order(size_t(f.channels));
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return spec.elevation_rad[size_t(a)] > spec.elevation_rad[size_t(b)]; });
    std::vector<int> row_of(size_t(f.channels));
    for (int r = 0; r < f.channels; ++r) row_of[size_t(order[size_t(r)])] = r;
    // Columns by each beam's own azimuth (destaggered: channels with azimuth offsets line up),
    // straight ahead in the middle, left on the left.
    if (!(range_max_m > 0)) {  // the shade's scale: the 99th percentile of the frame's ranges
        std::vector<float> r;
        for (const LidarPoint& p : f.points) r.push_back(p.range_m);
        if (!r.empty()) std::nth_element(r.begin(), r.begin() + long(r.size() * 99 / 100), r.end());
        range_max_m = r.empty() ? 1.0 : std::max(0.1, double(r[r.size() * 99 / 100]));
    }
    const int rep = std::max(1, f.columns / (4 * f.channels));
    Image im(f.columns, f.channels * rep, 3);
    for (const LidarPoint& p : f.points) {
        if (p.return_index != 0 || p.ring >= f.channels) continue;
        const double az = std::atan2(double(p.y), double(p.x));
        const long c = ((f.columns / 2 - std::lround(az * f.columns / (2 * M_PI))) % f.columns + f.columns) % f.columns;
        const float s = float(1 - 0.85 * std::min(1.0, std::sqrt(double(p.range_m) / range_max_m)));
        const bool smoke = p.source == uint8_t(EchoSource::Smoke);
        for (int k = 0; k < rep; ++k)
            put(im, int(c), row_of[p.ring] * rep + k, s, smoke ? 0.55f * s : s, smoke ? 0.1f * s : s);
    }
    return im;
}

Image topView(const LidarFrame& f, double half_width_m, int size_px)
{
    Image im(size_px, size_px, 3);
    std::fill(im.data.begin(), im.data.end(), 1.0f);
    const double scale = size_px / (2 * half_width_m);
    auto pixel = [&](double x, double y) {
        return std::pair<int, int>{int(std::floor((x + half_width_m) * scale)),
                                   int(std::floor((half_width_m - y) * scale))};
    };
    // Surfaces first, smoke on top of them.
    for (int pass = 0; pass < 2; ++pass)
        for (const LidarPoint& p : f.points) {
            const bool is_smoke = p.source == uint8_t(EchoSource::Smoke);
            if (is_smoke != (pass == 1)) continue;
            const auto [x, y] = pixel(p.x, p.y);
            if (is_smoke)
                put(im, x, y, 0.95f, 0.5f, 0.05f);
            else
                put(im, x, y, 0.25f, 0.25f, 0.25f);
        }
    const auto [sx, sy] = pixel(0, 0);
    for (int dx = -3; dx <= 3; ++dx)
        for (int dy = -3; dy <= 3; ++dy) put(im, sx + dx, sy + dy, 0.85f, 0.0f, 0.0f);
    return im;
}

}  // namespace smokescan
