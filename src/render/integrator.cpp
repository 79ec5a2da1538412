// The volumetric path tracer: spectral tracking through the smoke, next-event estimation to the
// scene's lights with ratio-tracked shadow rays, Henyey–Greenstein scattering, a Lambert + GGX
// surface model, Russian roulette. Lights are sampled only by next-event estimation (they are not
// geometry), the uniform ambient only by paths that escape, so each is counted exactly once.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>

#include "bsdf.hpp"
#include "integrator.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/render/renderer.hpp"
#include "sphere_rect.hpp"

namespace smokescan {
namespace {

struct LightSample {
    Vec3 wi = Vec3::UnitZ();  ///< direction towards the light
    double dist = kInf;
    Rgb Li = Rgb::Zero();  ///< incident radiance / pdf (or irradiance for delta lights)
};

class LightSet {
public:
    explicit LightSet(const Scene& s)
    {
        for (const auto& l : s.lights) {
            if (l.kind == LightKind::Ambient)
                ambient_ += l.radiance * l.color.array();
            else
                lights_.push_back(&l);
        }
    }
    const Rgb& ambient() const { return ambient_; }

    /// A point on an area light seen from p; solid_angle > 0 when sampled by solid angle.
    static Vec3 sampleArea(const Light& l, const Vec3& p, KeyedRng& rng, double& solid_angle)
    {
        const Vec3 ex = l.width_m * l.pose.R.col(1), ey = l.height_m * l.pose.R.col(2);
        const Vec3 corner = l.pose.t - 0.5 * ex - 0.5 * ey;
        const SphericalRectangle sr(p, corner, ex, ey);
        const double u = rng.uniform(), v = rng.uniform();
        if (!sr.usable()) return corner + u * ex + v * ey;  // too far or too flat for the spherical parametrisation
        solid_angle = sr.solidAngle();
        return sr.sample(u, v);
    }
    bool empty() const { return lights_.empty(); }

    /// One light chosen uniformly; the estimate is scaled by the number of lights.
    LightSample sample(const Vec3& p, KeyedRng& rng) const
    {
        LightSample ls;
        if (lights_.empty()) return ls;
        const size_t k = std::min(lights_.size() - 1, size_t(rng.uniform() * lights_.size()));
        const Light& l = *lights_[k];
        const double n = double(lights_.size());
        const double flux = l.power_w * l.efficiency;
        const Vec3 X = l.pose.R.col(0);
        if (l.kind == LightKind::Directional) {
            ls.wi = -X;
            ls.Li = n * l.irradiance * l.color.array();
            return ls;
        }
        Vec3 q = l.pose.t;
        double solid_angle = 0;  // > 0 when the area light was sampled by solid angle
        if (l.kind == LightKind::Area) q = sampleArea(l, p, rng, solid_angle);
        const Vec3 d = q - p;
        ls.dist = d.norm();
        if (!(ls.dist > 1e-9)) return ls;
        ls.wi = d / ls.dist;
        const double cos_l = X.dot(-ls.wi);  // area and spot lights face local +x
        const double inv_d2 = 1.0 / (ls.dist * ls.dist);
        double area_term = 1.0;
        switch (l.kind) {
        case LightKind::Area: {
            if (cos_l <= 0) return ls;  // one-sided emitter
            const double A = l.width_m * l.height_m, Le = flux / (M_PI * A);
            area_term = solid_angle > 0 ? Le * solid_angle : Le * cos_l * A * inv_d2;  // radiance / pdf(ω)
            break;
        }
        case LightKind::Point:
            area_term = flux / (4 * M_PI) * inv_d2;
            break;
        case LightKind::Spot: {  // a hard cone of half-angle spot_angle_deg
            const double c = std::cos(l.spot_angle_deg * M_PI / 180.0);
            area_term = cos_l >= c ? flux / (2 * M_PI * (1 - c)) * inv_d2 : 0.0;
            break;
        }
        case LightKind::Directional:
        case LightKind::Ambient:
            break;  // handled above and in the constructor
        }
        ls.Li = n * area_term * l.color.array();
        return ls;
    }

private:
    std::vector<const Light*> lights_;
    Rgb ambient_ = Rgb::Zero();
};

struct Context {
    const Scene& scene;
    const SurfaceSet& surfaces;
    const RenderMedium& medium;
    const LightSet& lights;
    const RenderConfig& cfg;
};

inline Vec3 offsetAlong(const Vec3& p, const Vec3& n) { return p + n * (1e-5 * (1.0 + p.cwiseAbs().maxCoeff())); }

/// Visibility × transmittance from p towards a light sample.
Rgb shadow(const Context& c, const Vec3& p, const LightSample& ls, KeyedRng& rng)
{
    const Ray r{p, ls.wi};
    const double reach = std::isfinite(ls.dist) ? ls.dist * (1 - 1e-6) : kInf;
    if (c.surfaces.closest(r, reach).hit) return Rgb::Zero();
    return c.medium.empty() ? Rgb::Ones() : c.medium.transmittance(r, reach, rng);
}

Rgb radiance(const Context& c, Ray ray, KeyedRng& rng)
{
    Rgb L = Rgb::Zero(), beta = Rgb::Ones();
    for (int depth = 0;;) {
        const SurfaceHit hit = c.surfaces.closest(ray, kInf);
        const MediumEvent ev = c.medium.empty() ? MediumEvent{} : c.medium.sample(ray, hit.endOr(kInf), beta, rng);
        if (ev.kind == MediumEvent::Absorb) break;
        if (ev.kind == MediumEvent::Escape && !hit.hit) {
            L += beta * c.lights.ambient();
            break;
        }
        if (++depth > c.cfg.max_depth) break;
        if (ev.kind == MediumEvent::Scatter) {
            const Vec3 p = ray.at(ev.t);
            if (!c.lights.empty()) {
                const LightSample ls = c.lights.sample(p, rng);
                if ((ls.Li > 0).any()) L += beta * ls.Li * hgPhase(ls.wi.dot(ray.d), ev.g) * shadow(c, p, ls, rng);
            }
            const double u1 = rng.uniform(), u2 = rng.uniform();
            ray = Ray{p, sampleHg(ray.d, ev.g, u1, u2)};
        } else {
            const Material& m = c.scene.materials[size_t(hit.material)];
            const Vec3 p = ray.at(hit.t_m), wo = -ray.d;
            const Bsdf bsdf(m, hit.normal);
            const Vec3 po = offsetAlong(p, hit.normal);
            if (!c.lights.empty()) {
                const LightSample ls = c.lights.sample(p, rng);
                const double cos_i = ls.wi.dot(hit.normal);
                if (cos_i > 0 && (ls.Li > 0).any())
                    L += beta * ls.Li * bsdf.eval(wo, ls.wi) * cos_i * shadow(c, po, ls, rng);
            }
            Vec3 wi;
            Rgb w;
            const double u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
            if (!bsdf.sample(wo, u0, u1, u2, wi, w)) break;
            beta *= w;
            ray = Ray{po, wi};
        }
        if (depth >= c.cfg.rr_depth) {
            const double q = std::min(0.95, beta.maxCoeff());
            if (!(q > 0) || rng.uniform() >= q) break;
            beta /= q;
        }
    }
    return L;
}

class Progress {
public:
    explicit Progress(bool on, long long total) : on_(on && ::isatty(2)), total_(total), start_(Clock::now()) {}
    void add(long long n)
    {
        if (!on_) return;
        const long long d = done_ += n;
        std::lock_guard<std::mutex> lock(m_);
        const double el = std::chrono::duration<double>(Clock::now() - start_).count();
        if (d < total_ && el - last_ < 0.2) return;
        last_ = el;
        const double f = double(d) / total_;
        const int w = 30, k = int(f * w);
        std::fprintf(stderr, "\rrender [%.*s%*s] %3d%%  %.1f s, ETA %.1f s ", k,
                     "==============================", w - k, "", int(100 * f), el, f > 0 ? el * (1 - f) / f : 0.0);
        if (d >= total_) std::fprintf(stderr, "\n");
    }

private:
    using Clock = std::chrono::steady_clock;
    bool on_;
    long long total_;
    std::atomic<long long> done_{0};
    std::mutex m_;
    Clock::time_point start_;
    double last_ = -1;
};

}  // namespace

RenderResult render(const Scene& scene, const SurfaceSet& surfaces, const RenderConfig& cfg)
{
    if (scene.cameras.empty()) throw Error(scene.source, "the scene has no camera to render");
    const Camera* cam = scene.findCamera(cfg.camera);
    if (!cam) throw Error(scene.source, "no camera named '" + cfg.camera + "'");
    Camera c = *cam;
    if (cfg.width < 0 || cfg.height < 0) throw Error("--width", "resolution must be > 0");
    if (cfg.width > 0) c.width = cfg.width;
    if (cfg.height > 0) c.height = cfg.height;
    return render(scene, surfaces, *makeCamera(c), cfg);
}

RenderResult render(const Scene& scene, const SurfaceSet& surfaces, const CameraModel& camera, const RenderConfig& cfg)
{
    if (!std::isfinite(cfg.time_s)) throw Error("--time", "must be finite");
    const auto t0 = std::chrono::steady_clock::now();
    const RenderMedium medium(SmokeField::at(scene.volumes, cfg.time_s), cfg.majorant_cells);
    RenderResult r = renderWithMedium(scene, surfaces, camera, medium, cfg);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

RenderResult renderWithMedium(const Scene& scene, const SurfaceSet& surfaces, const CameraModel& camera,
                              const RenderMedium& medium, const RenderConfig& cfg)
{
    if (cfg.spp < 1 || cfg.spp > limits::kSpp)
        throw Error("--spp", "must be in [1, " + std::to_string(limits::kSpp) + "]");
    if (cfg.max_depth < 0 || cfg.max_depth > limits::kPathDepth)
        throw Error("--max-depth", "must be in [0, " + std::to_string(limits::kPathDepth) + "]");
    if (camera.width() <= 0 || camera.height() <= 0) throw Error("camera", "resolution must be > 0");
    const int64_t pixels = int64_t(camera.width()) * camera.height();
    if (camera.width() > limits::kFrameSide || camera.height() > limits::kFrameSide || pixels > limits::kFramePixels)
        throw Error("--width",
                    std::to_string(camera.width()) + "x" + std::to_string(camera.height()) + " is over the " +
                        std::to_string(limits::kFrameSide) + " px a side and " + std::to_string(limits::kFramePixels) +
                        " pixels a frame may have");
    if (double(pixels) * cfg.spp > double(limits::kFrameSamples))
        throw Error("--spp",
                    "pixels × spp is over the " + std::to_string(limits::kFrameSamples) + " samples a frame may have");
    const auto t0 = std::chrono::steady_clock::now();
    const LightSet lights(scene);
    const Context ctx{scene, surfaces, medium, lights, cfg};
    const int W = camera.width(), H = camera.height();
    RenderResult res;
    res.radiance = Image(W, H, 3);
    res.variance = Image(W, H, 3);
    res.ids = Image(W, H, 3);
    res.ids.channel_names = {"object", "material", "depth"};
    constexpr int kTile = 16;
    const int tx = (W + kTile - 1) / kTile, ty = (H + kTile - 1) / kTile;
    Progress progress(cfg.progress, (long long)tx * ty);
    tbb::parallel_for(tbb::blocked_range<int>(0, tx * ty), [&](const tbb::blocked_range<int>& r) {
        for (int tile = r.begin(); tile != r.end(); ++tile) {
            const int x0 = (tile % tx) * kTile, y0 = (tile / tx) * kTile;
            for (int y = y0; y < std::min(H, y0 + kTile); ++y)
                for (int x = x0; x < std::min(W, x0 + kTile); ++x) {
                    const uint64_t pix = uint64_t(y) * W + x;
                    Ray centre;
                    if (camera.generateRay(x + 0.5, y + 0.5, centre)) {
                        const SurfaceHit h = surfaces.closest(centre, kInf);
                        res.ids.at(x, y, 0) = float(h.surface);
                        res.ids.at(x, y, 1) = float(h.material);
                        res.ids.at(x, y, 2) = h.hit ? float(h.t_m) : INFINITY;
                    } else {
                        res.ids.at(x, y, 0) = res.ids.at(x, y, 1) = -1.0f;
                        res.ids.at(x, y, 2) = INFINITY;
                    }
                    Rgb sum = Rgb::Zero(), sum2 = Rgb::Zero();
                    for (int s = 0; s < cfg.spp; ++s) {
                        KeyedRng rng(cfg.seed, pix, uint64_t(s));
                        Ray ray;
                        Rgb v = Rgb::Zero();
                        if (camera.generateRay(x + rng.uniform(), y + rng.uniform(), ray)) v = radiance(ctx, ray, rng);
                        if (!v.allFinite()) v.setZero();  // a numerical failure must not poison the pixel
                        sum += v;
                        sum2 += v * v;
                    }
                    const Rgb mean = sum / cfg.spp;
                    const Rgb var =
                        cfg.spp > 1 ? Rgb(((sum2 - sum * mean) / (cfg.spp - 1)).max(0.0) / cfg.spp) : Rgb(Rgb::Zero());
                    for (int k = 0; k < 3; ++k) {
                        res.radiance.at(x, y, k) = float(mean[k]);
                        res.variance.at(x, y, k) = float(var[k]);
                    }
                }
            progress.add(1);
        }
    });
    res.samples = (long long)W * H * cfg.spp;
    res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
}

double srgbEncode(double v)
{
    v = std::clamp(v, 0.0, 1.0);
    return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
}

Image toDisplay(const Image& rad, double exposure, double* used)
{
    double scale = exposure;
    if (!(scale > 0)) {
        double sum = 0;
        for (int y = 0; y < rad.height; ++y)
            for (int x = 0; x < rad.width; ++x)
                sum += 0.2126 * rad.at(x, y, 0) + 0.7152 * rad.at(x, y, 1) + 0.0722 * rad.at(x, y, 2);
        const double mean = sum / std::max(1, rad.width * rad.height);
        scale = mean > 0 ? 0.18 / mean : 1.0;
    }
    if (used) *used = scale;
    Image out(rad.width, rad.height, 3);
    for (size_t i = 0; i < out.data.size(); ++i) out.data[i] = float(srgbEncode(scale * rad.data[i]));
    return out;
}

}  // namespace smokescan
