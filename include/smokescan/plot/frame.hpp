#pragma once
/// @file frame.hpp
/// @brief A plot frame on a Canvas: a data box mapped into a pixel box, with ticks and labels.
/// Shared by the fit's and the diagnosis' report plots.
#include <algorithm>
#include <cmath>
#include <string>

#include "smokescan/core/format.hpp"
#include "smokescan/plot/canvas.hpp"

namespace smokescan {

/// Data ranges [ux0, ux1] × [uy0, uy1] mapped into the pixel box (x0, y0)–(x1, y1), y0 on top;
/// values outside the y range are drawn on its edge.
struct Frame {
    int x0, y0, x1, y1;  // pixel box (y0 top)
    double ux0, ux1, uy0, uy1;
    int X(double u) const { return int(std::lround(x0 + (x1 - x0) * (u - ux0) / (ux1 - ux0))); }
    int Y(double v) const { return int(std::lround(y1 - (y1 - y0) * (std::clamp(v, uy0, uy1) - uy0) / (uy1 - uy0))); }
    void axes(Canvas& c, const std::string& xl, const std::string& yl, const char* xf, const char* yf) const
    {
        c.line(x0, y1, x1, y1, {0, 0, 0});
        c.line(x0, y0, x0, y1, {0, 0, 0});
        for (int k = 0; k <= 5; ++k) {
            const double xv = ux0 + (ux1 - ux0) * k / 5, yv = uy0 + (uy1 - uy0) * k / 5;
            c.line(X(xv), y1, X(xv), y1 + 5, {0, 0, 0});
            c.text(X(xv) - 18, y1 + 20, fmt(xf, xv), 12);
            c.line(x0 - 5, Y(yv), x0, Y(yv), {0, 0, 0});
            c.text(x0 - 52, Y(yv) + 4, fmt(yf, yv), 12);
        }
        c.text((x0 + x1) / 2 - 60, y1 + 40, xl, 13);
        c.text(x0, y0 - 8, yl, 13);
    }
};

}  // namespace smokescan
