#include "smokescan/omni/omni_plots.hpp"

#include <algorithm>
#include <cmath>

#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/io/image.hpp"
#include "smokescan/plot/canvas.hpp"
#include "smokescan/plot/frame.hpp"

namespace smokescan {

void writeDifferenceHistogram(const std::string& path, const std::vector<double>& d, double outlier_m,
                              const std::string& title)
{
    const double w = 0.05;
    const int nb = std::max(1, int(std::ceil(2 * outlier_m / w)));
    std::vector<long long> bins(size_t(nb), 0);
    double sum = 0, sum2 = 0;
    for (double v : d) {
        bins[size_t(std::clamp(int(std::floor((v + outlier_m) / w)), 0, nb - 1))]++;
        sum += v;
        sum2 += v * v;
    }
    const double n = double(std::max<size_t>(1, d.size())), mean = sum / n;
    const double sd = std::sqrt(std::max(0.0, sum2 / n - mean * mean));
    const long long top = std::max<long long>(1, *std::max_element(bins.begin(), bins.end()));
    const int W = 720, H = 440;
    Canvas c(W, H);
    const Frame f{80, 50, W - 30, H - 70, -outlier_m, outlier_m, 0.0, double(top)};
    for (int b = 0; b < nb; ++b)
        if (bins[size_t(b)] > 0)
            c.box(f.X(-outlier_m + b * w) + 1, f.Y(double(bins[size_t(b)])), f.X(-outlier_m + (b + 1) * w) - 1, f.y1,
                  {0.25f, 0.45f, 0.75f}, true);
    c.line(f.X(0), f.y0, f.X(0), f.y1, {0.6f, 0.6f, 0.6f});
    f.axes(c, "laser - omnicam [m]", "scanlines", "%.2f", "%.0f");
    c.text(f.x0 + 10, 28, title, 15);
    c.text(f.x1 - 250, f.y0 + 20, fmt("n %.0f, mean %+.3f m, sd %.3f m", double(d.size()), mean, sd), 12);
    writeImage(path, c.image());
}

void writePixelDistancePlot(const std::string& path, const OmniCamera& cam, double height_m, double max_range_m)
{
    if (!(height_m > 0) || !(max_range_m > 0)) throw Error(path, "height and range must be > 0");
    const double rho_max = cam.radius(std::atan2(max_range_m, height_m));
    const double ymax = 1.1 * max_range_m;
    const int W = 720, H = 440;
    Canvas c(W, H);
    const Frame f{80, 50, W - 80, H - 70, 0.0, std::ceil(rho_max / 10) * 10, 0.0, ymax};
    // The error per pixel on its own scale (right): up to its value at the maximum range.
    const double emax = 1.1 * (cam.floorDistance(rho_max + 1, height_m) - max_range_m);
    int px = -1, py = -1, ex = -1, ey = -1;
    for (double r = 0; r <= rho_max; r += 0.25) {
        const double d = cam.floorDistance(r, height_m), e = cam.floorDistance(r + 1, height_m) - d;
        const int x = f.X(r), y = f.Y(d), y2 = f.Y(e / emax * ymax);
        if (px >= 0) {
            c.line(px, py, x, y, {0.15f, 0.3f, 0.7f});
            c.line(ex, ey, x, y2, {0.8f, 0.25f, 0.1f});
        }
        px = x, py = y, ex = x, ey = y2;
    }
    f.axes(c, "pixel distance from the centre [px]", "floor distance [m] (blue)", "%.0f", "%.1f");
    for (int k = 0; k <= 5; ++k)
        c.text(f.x1 + 8, f.Y(ymax * k / 5) + 4, fmt("%.3f", emax * k / 5), 12, {0.8f, 0.25f, 0.1f});
    c.text(f.x1 - 140, f.y0 - 8, "one pixel's error [m] (red)", 13, {0.8f, 0.25f, 0.1f});
    c.text(f.x0 + 10, f.y0 + 20,
           fmt("h = %.3f m, R = %.0f px: %.3f m a pixel at 1 m, %.3f m at %.1f m", height_m,
               cam.intrinsics().mirror_radius,
               cam.floorDistance(cam.radius(std::atan2(1.0, height_m)) + 1, height_m) - 1.0,
               cam.floorDistance(rho_max + 1, height_m) - max_range_m, max_range_m),
           12);
    writeImage(path, c.image());
}

void writeOccupancyGrids(const std::string& path, const std::vector<OmniFrame>& frames, const OccupancyConfig& cfg)
{
    if (!(cfg.cell_m > 0) || !(cfg.range_m > 0)) throw Error(path, "occupancy cell and range must be > 0");
    if (frames.empty()) throw Error(path, "no frames to map");
    // The area: every pose and every beam's end, and half a metre round them.
    double x0 = kInf, y0 = kInf, x1 = -kInf, y1 = -kInf;
    auto extend = [&](const Vec3& p) {
        x0 = std::min(x0, p.x()), x1 = std::max(x1, p.x()), y0 = std::min(y0, p.y()), y1 = std::max(y1, p.y());
    };
    for (const OmniFrame& f : frames) {
        extend(f.laser_pose.t);
        for (size_t b = 0; b < f.laser_range_m.size(); ++b) {
            const double r = f.laser_range_m[b], a = f.laser_angle_rad[b];
            if (std::isfinite(r) && r <= cfg.range_m) extend(scanPlanePoint(f.laser_pose, a, r));
        }
        for (size_t b = 0; b < f.omni.range_m.size(); ++b) {
            const double r = f.omni.range_m[b], a = f.omni.angle_rad[b];
            extend(scanPlanePoint(f.camera_pose, a, r));
        }
    }
    x0 -= 0.5, y0 -= 0.5, x1 += 0.5, y1 += 0.5;
    const int nx = int(std::ceil((x1 - x0) / cfg.cell_m)), ny = int(std::ceil((y1 - y0) / cfg.cell_m));
    if (double(nx) * 2 * ny > double(limits::kFramePixels)) throw Error(path, "the map would be too large");
    // Counts per cell: free passes and hits, for each sensor.
    std::vector<int> free[2], hit[2];
    for (int s = 0; s < 2; ++s) {
        free[s].assign(size_t(nx) * ny, 0);
        hit[s].assign(size_t(nx) * ny, 0);
    }
    auto cell = [&](const Vec3& p, int& i, int& j) {
        i = int(std::floor((p.x() - x0) / cfg.cell_m));
        j = int(std::floor((y1 - p.y()) / cfg.cell_m));
        return i >= 0 && j >= 0 && i < nx && j < ny;
    };
    auto ray = [&](int s, const Vec3& from, const Vec3& to, bool occupied) {
        const double len = (to - from).head<2>().norm();
        const int steps = std::max(1, int(len / (0.5 * cfg.cell_m)));
        int i, j;
        for (int k = 0; k < steps; ++k)
            if (cell(from + (to - from) * (double(k) / steps), i, j)) free[s][size_t(j) * nx + i]++;
        if (occupied && cell(to, i, j)) hit[s][size_t(j) * nx + i]++;
    };
    for (const OmniFrame& f : frames) {
        for (size_t b = 0; b < f.laser_range_m.size(); ++b) {
            const double r = f.laser_range_m[b], a = f.laser_angle_rad[b];
            const bool ok = std::isfinite(r) && r <= cfg.range_m;
            const double rr = ok ? r : cfg.range_m;
            ray(0, f.laser_pose.t, scanPlanePoint(f.laser_pose, a, rr), ok);
        }
        for (size_t b = 0; b < f.omni.range_m.size(); ++b) {
            const double r = f.omni.range_m[b], a = f.omni.angle_rad[b];
            ray(1, f.camera_pose.t, scanPlanePoint(f.camera_pose, a, r), f.omni.status[b] == OmniRangeStatus::Hit);
        }
    }
    Image img(2 * nx + 10, ny, 3);
    for (int s = 0; s < 2; ++s)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                const size_t k = size_t(j) * nx + i;
                float v = 0.75f;  // unknown
                if (hit[s][k] > 0 && hit[s][k] * 4 >= free[s][k])
                    v = 0.0f;
                else if (free[s][k] > 0)
                    v = 1.0f;
                for (int ch = 0; ch < 3; ++ch) img.at(s * (nx + 10) + i, j, ch) = v;
            }
    for (const OmniFrame& f : frames) {  // the path
        int i, j;
        if (!cell(f.laser_pose.t, i, j)) continue;
        for (int s = 0; s < 2; ++s) {
            img.at(s * (nx + 10) + i, j, 0) = 1.0f;
            img.at(s * (nx + 10) + i, j, 1) = img.at(s * (nx + 10) + i, j, 2) = 0.0f;
        }
    }
    writeImage(path, img);
}

}  // namespace smokescan
