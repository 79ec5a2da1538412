// The calibration plot (the smoke paper's Fig. 7).
#include <cmath>
#include <cstdio>

#include "smokescan/calib/calibration.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/io/image.hpp"
#include "smokescan/plot/canvas.hpp"
#include "smokescan/plot/palette.hpp"

namespace smokescan {
namespace {

/// Standard error of the fitted curve at ρ (delta method with the parameters' covariance).
double curveSe(const CurveFitResult& f, double rho)
{
    Eigen::Vector3d g;
    const double p[3] = {f.curve.S0, f.curve.a, f.curve.b};
    for (int k = 0; k < 3; ++k) {
        const double h = 1e-6 * std::max(1e-9, std::abs(p[k]));
        SaturationCurve up = f.curve, dn = f.curve;
        (k == 0 ? up.S0 : k == 1 ? up.a : up.b) += h;
        (k == 0 ? dn.S0 : k == 1 ? dn.a : dn.b) -= h;
        g[k] = (up(rho) - dn(rho)) / (2 * h);
    }
    return std::sqrt(std::max(0.0, g.dot(f.covariance * g)));
}

}  // namespace

void writeCalibrationPlot(const std::string& path, const CalibrationResult& r, const CalibrateConfig& cfg)
{
    const int W = 820, H = 540, L = 90, R = 30, T = 50, B = 70;
    double xmax = 0, ymax = 0;
    for (const auto& p : r.points) {
        xmax = std::max(xmax, p.density);
        ymax = std::max(ymax, p.saturation);
    }
    for (const auto& [n, pts] : r.patches)
        for (const auto& p : pts) ymax = std::max(ymax, p.saturation);
    xmax = xmax > 0 ? xmax * 1.05 : 1.0;
    ymax = std::max(0.2, ymax * 1.12);
    auto X = [&](double rho) { return int(std::lround(L + (W - L - R) * rho / xmax)); };
    auto Y = [&](double s) { return int(std::lround(H - B - (H - T - B) * s / ymax)); };
    Canvas c(W, H);

    // 95 % confidence band, then the curve.
    for (int px = X(0); px <= X(xmax); ++px) {
        const double rho = (px - L) * xmax / (W - L - R), s = r.fit.curve(rho), se = curveSe(r.fit, rho);
        c.line(px, Y(std::min(ymax, s + 1.96 * se)), px, Y(std::max(0.0, s - 1.96 * se)), {0.78f, 0.85f, 0.97f});
    }
    for (int px = X(0); px < X(xmax); ++px) {
        const double r0 = (px - L) * xmax / (W - L - R), r1 = (px + 1 - L) * xmax / (W - L - R);
        c.line(px, Y(r.fit.curve(r0)), px + 1, Y(r.fit.curve(r1)), {0.1f, 0.2f, 0.7f});
    }
    // Axes, ticks, labels.
    c.line(L, H - B, W - R, H - B, {0, 0, 0});
    c.line(L, T, L, H - B, {0, 0, 0});
    for (int k = 0; k <= 5; ++k) {
        const double xv = xmax * k / 5, yv = ymax * k / 5;
        c.line(X(xv), H - B, X(xv), H - B + 6, {0, 0, 0});
        c.text(X(xv) - 22, H - B + 24, fmt("%.4f", xv), 13);
        c.line(L - 6, Y(yv), L, Y(yv), {0, 0, 0});
        c.text(L - 48, Y(yv) + 5, fmt("%.2f", yv), 13);
    }
    c.text(L + (W - L - R) / 2 - 90, H - 18, "smoke density (engine units)", 15);
    c.text(12, T - 18, "target HSV saturation", 15);
    c.text(W / 2 - 170, 26, "density vs saturation (smoke paper, Fig. 7)", 16);
    // Patches (small), then the combined points with 95 % error bars.
    size_t patch = 0;
    for (const auto& [name, pts] : r.patches) {
        const Col col = colourOf(name, patch++);
        for (const auto& p : pts)
            c.box(X(p.density) - 2, Y(p.saturation) - 2, X(p.density) + 2, Y(p.saturation) + 2, col, true);
    }
    for (const auto& p : r.points) {
        const int x = X(p.density);
        c.line(x, Y(p.saturation + 1.96 * p.sigma), x, Y(std::max(0.0, p.saturation - 1.96 * p.sigma)), {0, 0, 0});
        c.box(x - 3, Y(p.saturation) - 3, x + 3, Y(p.saturation) + 3, {0, 0, 0}, true);
    }
    // The threshold: S = 0.14 and the density it maps to.
    const int ys = Y(cfg.threshold_saturation), xs = X(std::min(xmax, r.threshold_density));
    for (int x = L; x < W - R; x += 12) c.line(x, ys, std::min(W - R, x + 6), ys, {0.8f, 0.1f, 0.1f});
    for (int y = T; y < H - B; y += 12) c.line(xs, y, xs, std::min(H - B, y + 6), {0.8f, 0.1f, 0.1f});
    c.box(xs - 5, ys - 5, xs + 5, ys + 5, {0.8f, 0.1f, 0.1f}, false);
    c.text(std::min(xs + 10, W - 330), ys - 10,
           "S = " + fmt("%.2f", cfg.threshold_saturation) + " at density " + fmt("%.5f", r.threshold_density) +
               " +/- " + fmt("%.5f", r.threshold_density_se),
           14, {0.8f, 0.1f, 0.1f});
    writeImage(path, c.image());
}

}  // namespace smokescan
