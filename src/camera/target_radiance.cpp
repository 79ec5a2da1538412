#include "smokescan/camera/target_radiance.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "smokescan/camera/develop.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"

namespace smokescan {
namespace {

/// One patch's pixels and its least-squares fit: monomials u^i·v^j (i + j ≤ degree) of the pixel
/// centre, scaled to [−1, 1] over the patch, fitted on the interior pixels (the pixel and its four
/// neighbours on the patch: no edge pixel mixes colours) and evaluated on all of them.
struct PatchFit {
    std::vector<int> pixels, interior;  ///< pixel indices (y·W + x)
    Eigen::MatrixXd basis_all, basis_in;
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr;

    static Eigen::MatrixXd basis(const std::vector<int>& px, int W, const Eigen::Vector4d& box, int degree)
    {
        int terms = 0;
        for (int d = 0; d <= degree; ++d) terms += d + 1;
        Eigen::MatrixXd B(long(px.size()), terms);
        for (size_t r = 0; r < px.size(); ++r) {
            const double u = (px[r] % W + 0.5 - box[0]) / box[1], v = (px[r] / W + 0.5 - box[2]) / box[3];
            int k = 0;
            for (int d = 0; d <= degree; ++d)
                for (int j = 0; j <= d; ++j) B(long(r), k++) = std::pow(u, d - j) * std::pow(v, j);
        }
        return B;
    }
};

/// The patch fits; throws when a patch has too few interior pixels for its field.
std::vector<PatchFit> patchFits(const std::vector<int>& patch_of, int W, int H, size_t patches, int degree)
{
    std::vector<PatchFit> fits(patches);
    for (int i = 0; i < W * H; ++i)
        if (patch_of[size_t(i)] >= 0) fits[size_t(patch_of[size_t(i)])].pixels.push_back(i);
    auto same = [&](int x, int y, int p) {
        return x >= 0 && y >= 0 && x < W && y < H && patch_of[size_t(y * W + x)] == p;
    };
    for (size_t p = 0; p < patches; ++p) {
        PatchFit& f = fits[p];
        if (f.pixels.empty()) continue;
        double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
        for (int i : f.pixels) {
            const int x = i % W, y = i / W;
            x0 = std::min(x0, x + 0.5), x1 = std::max(x1, x + 0.5), y0 = std::min(y0, y + 0.5),
            y1 = std::max(y1, y + 0.5);
            if (same(x - 1, y, int(p)) && same(x + 1, y, int(p)) && same(x, y - 1, int(p)) && same(x, y + 1, int(p)))
                f.interior.push_back(i);
        }
        const Eigen::Vector4d box(0.5 * (x0 + x1), std::max(0.5, 0.5 * (x1 - x0)), 0.5 * (y0 + y1),
                                  std::max(0.5, 0.5 * (y1 - y0)));
        f.basis_all = PatchFit::basis(f.pixels, W, box, degree);
        f.basis_in = PatchFit::basis(f.interior, W, box, degree);
        if (f.basis_in.rows() < 4 * f.basis_in.cols())
            throw Error("target",
                        "a patch shows " + std::to_string(f.interior.size()) +
                            " interior pixels, too few for its radiance field (a larger frame)");
        f.qr.compute(f.basis_in);
    }
    return fits;
}

}  // namespace

TargetRadiance measureTargetRadiance(const Scene& scene, const SurfaceSet& surfaces, const RenderConfig& rc0,
                                     const TargetPatches& target, const CameraSensor& sensor,
                                     const TargetRadianceConfig& cfg)
{
    if (cfg.meter_spp < 1 || cfg.batch_spp < 1 || cfg.min_batches < 2 || cfg.max_batches < cfg.min_batches ||
        cfg.max_batches > 4096 || !(cfg.rel_error > 0) || cfg.degree < 0 || cfg.degree > 8)
        throw Error("target radiance",
                    "needs spp >= 1, 2 <= min_batches <= max_batches <= 4096, rel_error > 0, degree in [0, 8]");
    // Each batch's frame is kept (and as many fields): bound the memory before any work.
    const double bytes = double(rc0.width) * rc0.height * 3 * sizeof(float) * (2.0 * cfg.max_batches + 2);
    if (bytes > double(limits::kConvergedBytes))
        throw Error("--max-batches",
                    "a converged measurement of " + std::to_string(rc0.width) + "x" + std::to_string(rc0.height) +
                        " px over " + std::to_string(cfg.max_batches) + " batches would hold " +
                        std::to_string(int(bytes / (1 << 20))) + " MiB of frames (at most " +
                        std::to_string(limits::kConvergedBytes >> 20) + " MiB): fewer batches or a smaller frame");
    RenderConfig rc = rc0;
    rc.spp = cfg.meter_spp;
    const RenderResult meter = render(scene, surfaces, rc);
    if (meter.stopped) throw Error("render", "stopped");  // its watch said so (renderer.hpp)
    TargetRadiance out;
    const int W = meter.radiance.width, H = meter.radiance.height;
    out.ids = meter.ids;
    out.exposure = meterExposure(meter.radiance, sensor);
    out.patch_of_pixel.assign(size_t(W) * H, -1);
    std::vector<uint8_t> mask(size_t(W) * H, 0);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const int p = target.of(int(meter.ids.at(x, y, 0)));
            out.patch_of_pixel[size_t(y * W + x)] = p;
            mask[size_t(y * W + x)] = p >= 0;
        }
    if (std::none_of(mask.begin(), mask.end(), [](uint8_t m) { return m; }))
        throw Error(scene.source, "the camera does not see the target");
    std::vector<PatchFit> fits = patchFits(out.patch_of_pixel, W, H, target.names.size(), cfg.degree);

    // Batches until the fitted patch means are known well enough.
    std::vector<Image> raw;  // per-pixel means of each batch
    std::vector<std::vector<Eigen::MatrixXd>> coef;  // [batch][patch] terms × 3
    rc.spp = cfg.batch_spp;
    rc.mask = &mask;
    for (int b = 0; b < cfg.max_batches; ++b) {
        rc.seed = rc0.seed ^ (uint64_t(b + 1) << 40);
        RenderResult batch = render(scene, surfaces, rc);
        if (batch.stopped) throw Error("render", "stopped");
        raw.push_back(std::move(batch.radiance));
        coef.emplace_back(fits.size());
        for (size_t p = 0; p < fits.size(); ++p) {
            if (fits[p].pixels.empty()) continue;
            Eigen::MatrixXd y(long(fits[p].interior.size()), 3);
            for (size_t r = 0; r < fits[p].interior.size(); ++r)
                for (int c = 0; c < 3; ++c)
                    y(long(r), c) = raw.back().data[size_t(fits[p].interior[r]) * 3 + size_t(c)];
            coef.back()[p] = fits[p].qr.solve(y);
        }
        const int B = b + 1;
        if (B < cfg.min_batches) continue;
        out.rel_error = 0;
        for (size_t p = 0; p < fits.size(); ++p) {
            if (fits[p].pixels.empty()) continue;
            const Eigen::RowVectorXd mean_basis = fits[p].basis_all.colwise().mean();
            Eigen::Array3d s = Eigen::Array3d::Zero(), s2 = Eigen::Array3d::Zero();
            for (int k = 0; k < B; ++k) {
                const Eigen::Array3d m = (mean_basis * coef[size_t(k)][p]).transpose().array();
                s += m;
                s2 += m * m;
            }
            const Eigen::Array3d mean = s / B, var = ((s2 - s * mean) / (B - 1)).max(0.0);
            out.rel_error = std::max(out.rel_error, ((var / B).sqrt() / mean.max(1e-30)).maxCoeff());
        }
        if (out.rel_error <= cfg.rel_error) break;
    }
    const int B = int(raw.size());
    out.spp = B * cfg.batch_spp;

    // The field: every batch's and their mean (the fit to the mean of the pixel means).
    out.radiance = meter.radiance;
    out.batches.assign(size_t(B), meter.radiance);
    for (size_t p = 0; p < fits.size(); ++p) {
        const PatchFit& f = fits[p];
        if (f.pixels.empty()) continue;
        Eigen::MatrixXd mean_coef = Eigen::MatrixXd::Zero(coef[0][p].rows(), 3);
        for (int k = 0; k < B; ++k) {
            mean_coef += coef[size_t(k)][p] / B;
            const Eigen::MatrixXd v = f.basis_all * coef[size_t(k)][p];
            for (size_t r = 0; r < f.pixels.size(); ++r)
                for (int c = 0; c < 3; ++c)
                    out.batches[size_t(k)].data[size_t(f.pixels[r]) * 3 + size_t(c)] =
                        float(std::max(0.0, v(long(r), c)));
        }
        const Eigen::MatrixXd v = f.basis_all * mean_coef, v_in = f.basis_in * mean_coef;
        for (size_t r = 0; r < f.pixels.size(); ++r)
            for (int c = 0; c < 3; ++c)  // radiance is not negative (an edge pixel's extrapolation can be)
                out.radiance.data[size_t(f.pixels[r]) * 3 + size_t(c)] = float(std::max(0.0, v(long(r), c)));
        // Lack of fit: the pixel means' scatter about the field against their noise, which the
        // batches measure (the variance of a pixel's mean over B batches).
        double rss = 0, noise = 0;
        for (size_t r = 0; r < f.interior.size(); ++r)
            for (int c = 0; c < 3; ++c) {
                const size_t i = size_t(f.interior[r]) * 3 + size_t(c);
                double s = 0, s2 = 0;
                for (const Image& im : raw) {
                    s += im.data[i];
                    s2 += double(im.data[i]) * im.data[i];
                }
                const double m = s / B;
                rss += (m - v_in(long(r), c)) * (m - v_in(long(r), c));
                noise += std::max(0.0, (s2 - s * m) / (B - 1)) / B;
            }
        const double dof = double(f.interior.size()) - double(f.basis_in.cols());
        out.lack_of_fit[target.names[p]] = noise > 0 ? (rss / dof) / (noise / double(f.interior.size())) : 0.0;
    }
    return out;
}

}  // namespace smokescan
