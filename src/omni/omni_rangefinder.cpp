#include "smokescan/omni/omni_rangefinder.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "smokescan/core/error.hpp"

namespace smokescan {
namespace {

/// Image radius [px] of the floor point at distance d_m, seen from height h_m.
double radiusAtRange(const OmniCamera& cam, double h_m, double d_m) { return cam.radius(std::atan2(d_m, h_m)); }

bool positiveFinite(double v) { return v > 0 && std::isfinite(v); }

void checkFrame(const Image& frame, const OmniCamera& cam)
{
    if (frame.width != cam.width() || frame.height != cam.height() || frame.channels < 3)
        throw Error("omnicam frame",
                    "is " + std::to_string(frame.width) + "x" + std::to_string(frame.height) + "x" +
                        std::to_string(frame.channels) + ", the camera's is " + std::to_string(cam.width()) + "x" +
                        std::to_string(cam.height()) + " RGB");
}

}  // namespace

void checkOmniRangeConfig(const OmniRangeConfig& cfg, const OmniCamera& cam)
{
    if (cfg.scanlines < 1 || cfg.scanlines > 36000) throw Error("--scanlines", "must lie in 1…36000");
    if (!(cfg.threshold > 0 && cfg.threshold <= 1)) throw Error("--threshold", "Θ must lie in (0, 1]");
    if (cfg.filter.n_behind < 1 || cfg.filter.n_behind > 10000)
        throw Error("--n-behind", "N must lie in 1…10000 pixels");
    if (cfg.filter.k_free < 1 || cfg.filter.k_free > 10000) throw Error("--k-free", "K must lie in 1…10000 pixels");
    if (!positiveFinite(cfg.height_m)) throw Error("omni camera", "its viewpoint must be above the floor (height > 0)");
    if (!positiveFinite(cfg.max_range_m) || cfg.max_range_m > 1000)
        throw Error("--max-range", "must lie in (0, 1000] m");
    if (!(cfg.min_range_m >= 0) || !(cfg.min_range_m < cfg.max_range_m))
        throw Error("--min-range", "must lie in [0, --max-range)");
    const OmniIntrinsics& k = cam.intrinsics();
    const double rho = radiusAtRange(cam, cfg.height_m, cfg.max_range_m) + cfg.filter.n_behind + 1;
    const double rim = cam.radius(k.max_incidence_deg * M_PI / 180);
    char where[160];
    std::snprintf(where, sizeof where, "the floor at %.3g m (image radius %.4g px with --n-behind pixels behind it)",
                  cfg.max_range_m, rho);
    if (rho > rim || rho > k.cx || rho > k.cy || rho > k.width - k.cx || rho > k.height - k.cy)
        throw Error("omni camera",
                    std::string("the mirror and mount put ") + where + " outside the image or the mirror's rim");
    if (k.base_radius >= radiusAtRange(cam, cfg.height_m, cfg.max_range_m))
        throw Error("omni camera", "base_radius_px hides the floor out to beyond --max-range");
}

OmniRangeResult omniRange(const Image& frame, const OmniCamera& cam, const ColourHistogram& hist,
                          const OmniRangeConfig& cfg)
{
    checkOmniRangeConfig(cfg, cam);
    checkFrame(frame, cam);
    const OmniIntrinsics& k = cam.intrinsics();
    const double rho0 = std::max(1.0, std::ceil(k.base_radius));
    const int n = int(std::ceil(radiusAtRange(cam, cfg.height_m, cfg.max_range_m) - rho0)) + cfg.filter.n_behind + 1;
    OmniRangeResult r;
    std::vector<bool> free(size_t(std::max(n, 0)));
    for (int s = 0; s < cfg.scanlines; ++s) {
        const double phi = 2 * M_PI * s / cfg.scanlines;
        const double c = std::cos(phi), sn = std::sin(phi);
        for (int i = 0; i < n; ++i) {
            const double rho = rho0 + i;
            const int x = std::clamp(int(std::floor(k.cx + rho * c)), 0, k.width - 1);
            const int y = std::clamp(int(std::floor(k.cy - rho * sn)), 0, k.height - 1);
            free[size_t(i)] = hist.isFree(frame.at(x, y, 0), frame.at(x, y, 1), frame.at(x, y, 2), cfg.threshold);
        }
        const int hit = findHitPoint(free, cfg.filter);
        double range = cfg.max_range_m, rho_hit = NAN;
        OmniRangeStatus st = OmniRangeStatus::MaxRange;
        if (hit >= 0) {
            // The pixel the obstacle's foot crosses mixes floor and obstacle and reads non-free,
            // so the foot lies at the hit's own sample radius (measured on a rendered court:
            // +0.12 px on average; half a pixel in, −0.36 px).
            rho_hit = rho0 + hit;
            const double d = cam.floorDistance(rho_hit, cfg.height_m);
            if (hit == 0 || d < cfg.min_range_m) {
                range = cfg.min_range_m;
                st = OmniRangeStatus::MinRange;
            } else if (d <= cfg.max_range_m) {
                range = d;
                st = OmniRangeStatus::Hit;
            }
        }
        r.angle_rad.push_back(phi > M_PI ? phi - 2 * M_PI : phi);
        r.range_m.push_back(range);
        r.status.push_back(st);
        r.hit_radius_px.push_back(rho_hit);
    }
    return r;
}

long long trainFreeSpace(ColourHistogram& hist, const Image& frame, const OmniCamera& cam, const LaserFreeSpace& laser,
                         const OmniRangeConfig& cfg, double margin_m, const std::vector<bool>* skip_scanline)
{
    checkFrame(frame, cam);
    const size_t nb = laser.angle_rad.size();
    if (nb < 2 || laser.range_m.size() != nb) throw Error("laser scan", "needs at least two beams, one range each");
    if (skip_scanline && skip_scanline->size() != size_t(cfg.scanlines))
        throw Error("skip_scanline", "needs one entry per scanline");
    const double step = 2 * M_PI / cfg.scanlines;
    const double half_step = 0.5 * (laser.angle_rad.back() - laser.angle_rad.front()) / double(nb - 1);
    const Vec3 o = cam.pose().t;
    long long counted = 0;
    for (int y = 0; y < frame.height; ++y)
        for (int x = 0; x < frame.width; ++x) {
            Ray ray;
            if (!cam.generateRay(x + 0.5, y + 0.5, ray) || !(ray.d.z() < -1e-9)) continue;
            const Vec3 p = ray.at(cfg.height_m / -ray.d.z());  // on the floor
            if (std::hypot(p.x() - o.x(), p.y() - o.y()) > cfg.max_range_m) continue;
            if (skip_scanline) {
                const Vec3 c = cam.pose().R.transpose() * (p - o);
                const long long s = std::llround(std::atan2(c.y(), c.x()) / step);
                if ((*skip_scanline)[size_t(((s % cfg.scanlines) + cfg.scanlines) % cfg.scanlines)]) continue;
            }
            const Vec3 q = laser.pose.R.transpose() * (p - laser.pose.t);
            const double a = std::atan2(q.y(), q.x()), dist = std::hypot(q.x(), q.y());
            // The nearest beam in bearing, the scan's two ends neighbours across ±π (a 360° laser).
            const auto it = std::lower_bound(laser.angle_rad.begin(), laser.angle_rad.end(), a);
            const size_t hi = size_t(it - laser.angle_rad.begin()) % nb, lo = (hi + nb - 1) % nb;
            auto gap = [&](size_t k) { return std::abs(std::remainder(a - laser.angle_rad[k], 2 * M_PI)); };
            const size_t i = gap(lo) < gap(hi) ? lo : hi;
            if (gap(i) > half_step + 1e-12) continue;  // outside the laser's field
            const double range = laser.range_m[i];
            if (!std::isfinite(range) || !(dist < range - margin_m)) continue;
            hist.add(frame.at(x, y, 0), frame.at(x, y, 1), frame.at(x, y, 2));
            ++counted;
        }
    return counted;
}

}  // namespace smokescan
