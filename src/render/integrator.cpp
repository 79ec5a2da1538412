// The volumetric path tracer: spectral tracking through the smoke, next-event estimation to the
// scene's lights with ratio-tracked shadow rays, Henyey–Greenstein scattering, a Lambert + GGX
// surface model, Russian roulette. Lights are sampled only by next-event estimation (they are not
// geometry), the uniform ambient only by paths that escape, so each is counted exactly once.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <algorithm>
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

    size_t size() const { return lights_.size(); }
    const Light& light(size_t k) const { return *lights_[k]; }
    /// A uniformly chosen light's index.
    size_t pick(KeyedRng& rng) const { return std::min(lights_.size() - 1, size_t(rng.uniform() * lights_.size())); }

    /// One light chosen uniformly; the estimate is scaled by the number of lights.
    LightSample sample(const Vec3& p, KeyedRng& rng) const
    {
        if (lights_.empty()) return LightSample{};
        return sampleLight(pick(rng), p, rng);
    }

    /// Light k seen from p, its estimate scaled by the number of lights (k was chosen uniformly).
    LightSample sampleLight(size_t k, const Vec3& p, KeyedRng& rng) const
    {
        const Light& l = *lights_[k];
        double solid_angle = 0;  // > 0 when the area light was sampled by solid angle
        const Vec3 q = l.kind == LightKind::Area ? sampleArea(l, p, rng, solid_angle) : l.pose.t;
        return lightFrom(k, q, p, solid_angle);
    }

    /// Light k's point q seen from p. Li is the incident radiance over the sample's density: by
    /// solid angle when solid_angle > 0 (area lights), else by area (uniform on the light).
    LightSample lightFrom(size_t k, const Vec3& q, const Vec3& p, double solid_angle) const
    {
        LightSample ls;
        const Light& l = *lights_[k];
        const double n = double(lights_.size());
        const double flux = l.power_w * l.efficiency;
        const Vec3 X = l.pose.R.col(0);
        if (l.kind == LightKind::Directional) {
            ls.wi = -X;
            ls.Li = n * l.irradiance * l.color.array();
            return ls;
        }
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

/// σ_s·p(cos θ) at p [1/(m·sr)], per channel: the components' phase functions mixed by σ_s.
Rgb scatterPhase(const RenderMedium& m, const Vec3& p, double cos_theta)
{
    Rgb s = Rgb::Zero();
    m.forEachScatterer(p, [&](const Rgb& ss, double g) { s += ss * hgPhase(cos_theta, g); });
    return s;
}

/// A direction after a collision at p (photon travelling along dir), drawn from the mixture of the
/// components' phase functions, each chosen by its channel-mean σ_s; w = σ_s·p(ω)/pdf(ω) per
/// channel, so each channel gets its own mixture exactly. False where there is no smoke.
bool sampleScatter(const RenderMedium& m, const Vec3& p, const Vec3& dir, KeyedRng& rng, Vec3& wi, Rgb& w)
{
    double total = 0, g_pick = 0;
    m.forEachScatterer(p, [&](const Rgb& ss, double) { total += ss.mean(); });
    const double pick = rng.uniform() * total, u1 = rng.uniform(), u2 = rng.uniform();
    if (!(total > 0)) return false;
    double acc = 0;
    bool chosen = false;
    m.forEachScatterer(p, [&](const Rgb& ss, double g) {
        acc += ss.mean();
        if (!chosen) g_pick = g;
        chosen = chosen || pick < acc;
    });
    wi = sampleHg(dir, g_pick, u1, u2);
    const double c = wi.dot(dir);
    double pdf = 0;
    Rgb f = Rgb::Zero();
    m.forEachScatterer(p, [&](const Rgb& ss, double g) {
        const double ph = hgPhase(c, g);
        pdf += ss.mean() / total * ph;
        f += ss * ph;
    });
    if (!(pdf > 0)) return false;
    w = f / pdf;
    return true;
}

/// Equiangular sampling (Kulla & Fajardo 2012) of t ∈ [t0, t1) along a ray, with density ∝ 1/d²
/// for d the distance to a point q: the in-scattered light of a small light source.
struct Equiangular {
    double mid = 0, D = 1, th0 = 0, th1 = 0;
    Equiangular(const Ray& r, const Vec3& q, double t0, double t1)
        : mid((q - r.o).dot(r.d)), D(std::max(1e-9, (r.o + mid * r.d - q).norm()))
    {
        th0 = std::atan((t0 - mid) / D);
        th1 = std::atan((t1 - mid) / D);
    }
    double sample(double u) const { return mid + D * std::tan(th0 + u * (th1 - th0)); }
    double pdf(double t) const
    {
        const double x = t - mid;
        return th1 > th0 ? D / ((th1 - th0) * (D * D + x * x)) : 0.0;
    }
};

/// The lights' direct light scattered towards the ray's origin by the smoke along [0, t_max),
/// attenuated on the way: one sample for one uniformly chosen light, the distance drawn by
/// one-sample MIS (balance heuristic) of equiangular sampling towards the light's centre and the
/// forced-collision density, the point on the light by solid angle from there. (Drawing the light's
/// point first, by area, and aiming the equiangular sample at it was tried: it cancels the 1/d² of
/// the near field exactly but cost 1.4–4× more variance per second in the BOCAS calibration.)
/// It replaces next-event estimation at collisions, whose 1/d² peak near a small light (the lamp
/// under the BOCAS laser) made the frames' noise heavy-tailed.
Rgb segmentDirect(const Context& c, const Ray& ray, double t_max, KeyedRng& rng)
{
    double t0 = 0, t1 = 0;
    const double u = rng.uniform(), us = rng.uniform();
    if (c.lights.empty() || !c.medium.clip(ray, t_max, t0, t1)) return Rgb::Zero();
    const size_t k = c.lights.pick(rng);
    const Light& l = c.lights.light(k);
    const bool positional = l.kind != LightKind::Directional;
    const Equiangular eq(ray, l.pose.t, t0, t1);
    double t = 0, pf = 0;
    if (positional && u < 0.5) {
        t = std::clamp(eq.sample(us), t0, t1);
        pf = c.medium.forcedPdf(ray, t_max, t);
    } else if (!c.medium.sampleForced(ray, t_max, us, t, pf)) {
        return Rgb::Zero();
    }
    const double pdf = positional ? 0.5 * (eq.pdf(t) + pf) : pf;
    if (!(pdf > 0) || !(t < t_max)) return Rgb::Zero();
    const Vec3 p = ray.at(t);
    const LightSample ls = c.lights.sampleLight(k, p, rng);
    if (!(ls.Li > 0).any()) return Rgb::Zero();
    const Rgb f = scatterPhase(c.medium, p, ls.wi.dot(ray.d));
    if (!(f > 0).any()) return Rgb::Zero();
    return c.medium.transmittance(ray, t, rng) * f * ls.Li * shadow(c, p, ls, rng) / pdf;
}

/// Continues a path leaving along `ray` with throughput beta after `depth` events. clear_first:
/// the first segment's smoke is accounted for already (the split primary ray).
Rgb trace(const Context& c, Ray ray, Rgb beta, int depth, KeyedRng& rng, bool clear_first = false)
{
    Rgb L = Rgb::Zero();
    const bool segment = c.cfg.segment_lighting && !c.lights.empty();
    for (bool first = true;; first = false) {
        const SurfaceHit hit = c.surfaces.closest(ray, kInf);
        const bool smoke = !c.medium.empty() && !(first && clear_first);
        if (smoke && segment && depth < c.cfg.max_depth) L += beta * segmentDirect(c, ray, hit.endOr(kInf), rng);
        const MediumEvent ev = smoke ? c.medium.sample(ray, hit.endOr(kInf), beta, rng) : MediumEvent{};
        if (ev.kind == MediumEvent::Absorb) break;
        if (ev.kind == MediumEvent::Escape && !hit.hit) {
            L += beta * c.lights.ambient();
            break;
        }
        if (++depth > c.cfg.max_depth) break;
        if (ev.kind == MediumEvent::Scatter) {
            const Vec3 p = ray.at(ev.t);
            if (!segment && !c.lights.empty()) {
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

/// A camera ray's radiance. With split_primary, the first segment is split in two: the surface
/// (or the environment) through the smoke's transmittance, always, and a forced collision in the
/// smoke from which the path scatters on. Without it a sample sees the target only when its free
/// flight happens to reach it, which in thick smoke is a rare, bright, coloured event.
Rgb radiance(const Context& c, const Ray& ray, KeyedRng& rng)
{
    if (!c.cfg.split_primary || c.medium.empty()) return trace(c, ray, Rgb::Ones(), 0, rng);
    const double t_end = c.surfaces.closest(ray, kInf).endOr(kInf);
    const bool segment = c.cfg.segment_lighting && !c.lights.empty();
    Rgb L = Rgb::Zero();
    if (segment && c.cfg.max_depth >= 1) L += segmentDirect(c, ray, t_end, rng);
    double t = 0, pdf = 0;
    const double u = rng.uniform();
    if (c.cfg.max_depth >= 1 && c.medium.sampleForced(ray, t_end, u, t, pdf)) {
        const Vec3 p = ray.at(t);
        const Rgb T = c.medium.transmittance(ray, t, rng) / pdf;
        if (!segment && !c.lights.empty()) {
            const LightSample ls = c.lights.sample(p, rng);
            if ((ls.Li > 0).any()) L += T * scatterPhase(c.medium, p, ls.wi.dot(ray.d)) * ls.Li * shadow(c, p, ls, rng);
        }
        Vec3 wi;
        Rgb w;
        if (sampleScatter(c.medium, p, ray.d, rng, wi, w)) L += trace(c, Ray{p, wi}, T * w, 1, rng);
    }
    const Rgb Ts = c.medium.transmittance(ray, t_end, rng);
    if ((Ts > 0).any()) L += trace(c, ray, Ts, 0, rng, true);
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
    Camera c = scene.cameraAt(*cam, cfg.time_s);  // on its robot, when it rides on one
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
    if (cfg.mask && cfg.mask->size() != size_t(pixels))
        throw Error("render", "the pixel mask's size is not the frame's width × height");
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
    if (cfg.watch) {
        cfg.watch->tiles_total = (long long)tx * ty;
        cfg.watch->tiles_done = 0;
    }
    std::atomic<bool> skipped{false};
    tbb::parallel_for(tbb::blocked_range<int>(0, tx * ty), [&](const tbb::blocked_range<int>& r) {
        for (int tile = r.begin(); tile != r.end(); ++tile) {
            if (cfg.watch && cfg.watch->stop) {
                skipped = true;
                return;
            }
            const int x0 = (tile % tx) * kTile, y0 = (tile / tx) * kTile;
            bool cut = false;  // stopped within this tile
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
                    if (cfg.mask && !(*cfg.mask)[size_t(pix)]) continue;
                    // A stop ends the frame within a pixel (a tile of many samples may take seconds).
                    if (cfg.watch && cfg.watch->stop) {
                        skipped = cut = true;
                        continue;
                    }
                    Rgb sum = Rgb::Zero(), sum2 = Rgb::Zero();
                    for (int s = 0; s < cfg.spp; ++s) {
                        KeyedRng rng(cfg.seed, pix, uint64_t(s));
                        Ray ray;
                        Rgb v = Rgb::Zero();
                        // y's jitter drawn first, in its own statement (as arguments of one call
                        // the order was the compiler's; gcc's, right to left, kept).
                        const double jy = rng.uniform();
                        const double jx = rng.uniform();
                        if (camera.generateRay(x + jx, y + jy, ray)) v = radiance(ctx, ray, rng);
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
            if (cfg.watch && !cut) ++cfg.watch->tiles_done;
        }
    });
    res.stopped = skipped;
    const long long rendered = cfg.mask
        ? (long long)std::count_if(cfg.mask->begin(), cfg.mask->end(), [](uint8_t m) { return m != 0; })
        : (long long)W * H;
    res.samples = rendered * cfg.spp;
    res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
}

double srgbEncode(double v)
{
    v = std::clamp(v, 0.0, 1.0);
    return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
}

Image toDisplay(const Image& rad, double exposure, double* used, const CameraModel* metered_by)
{
    double scale = exposure;
    if (!(scale > 0)) {
        double sum = 0;
        long long n = 0;
        Ray unused;
        for (int y = 0; y < rad.height; ++y)
            for (int x = 0; x < rad.width; ++x) {
                if (metered_by && !metered_by->generateRay(x + 0.5, y + 0.5, unused)) continue;
                sum += 0.2126 * rad.at(x, y, 0) + 0.7152 * rad.at(x, y, 1) + 0.0722 * rad.at(x, y, 2);
                ++n;
            }
        if (metered_by && n == 0)
            throw Error("--exposure",
                        "cannot meter: no pixel of the frame sees through the camera (its mirror's disc lies outside "
                        "the frame); give a scale");
        const double mean = sum / double(std::max(1LL, n));
        scale = mean > 0 ? 0.18 / mean : 1.0;
    }
    if (used) *used = scale;
    Image out(rad.width, rad.height, 3);
    for (size_t i = 0; i < out.data.size(); ++i) out.data[i] = float(srgbEncode(scale * rad.data[i]));
    return out;
}

}  // namespace smokescan
