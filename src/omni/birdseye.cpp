#include "smokescan/omni/birdseye.hpp"

#include <algorithm>
#include <cmath>

#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"

namespace smokescan {

Image birdseye(const Image& frame, const OmniCamera& cam, const BirdseyeConfig& cfg)
{
    if (cfg.size_px < 1 || cfg.size_px > limits::kFrameSide)
        throw Error("--birdseye-size", "must lie in 1…" + std::to_string(limits::kFrameSide));
    if (!(cfg.metres_per_px > 0) || !std::isfinite(cfg.metres_per_px))
        throw Error("--birdseye-scale", "must be finite and > 0");
    if (!(cfg.height_m > 0) || !std::isfinite(cfg.height_m)) throw Error("height_m", "must be finite and > 0");
    if (frame.width != cam.width() || frame.height != cam.height() || frame.channels < 3)
        throw Error("birdseye", "the frame is not the camera's size");
    const int n = cfg.size_px, c = frame.channels;
    Image out(n, n, 3);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double X = (i + 0.5 - 0.5 * n) * cfg.metres_per_px, Y = (0.5 * n - j - 0.5) * cfg.metres_per_px;
            const Vec3 p = cam.pose().apply(Vec3(X, Y, -cfg.height_m));
            const Vec2 px = cam.project(p);
            Ray probe;
            if (!cam.generateRay(px.x(), px.y(), probe)) continue;
            // Bilinear between pixel centres, clamped at the frame's border.
            const double fx = px.x() - 0.5, fy = px.y() - 0.5;
            const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
            const double ax = fx - x0, ay = fy - y0;
            auto at = [&](int x, int y, int k) {
                x = std::clamp(x, 0, frame.width - 1);
                y = std::clamp(y, 0, frame.height - 1);
                return double(frame.data[(size_t(y) * frame.width + x) * c + k]);
            };
            for (int k = 0; k < 3; ++k)
                out.at(i, j, k) = float((1 - ay) * ((1 - ax) * at(x0, y0, k) + ax * at(x0 + 1, y0, k)) +
                                        ay * ((1 - ax) * at(x0, y0 + 1, k) + ax * at(x0 + 1, y0 + 1, k)));
        }
    return out;
}

}  // namespace smokescan
