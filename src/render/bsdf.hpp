#pragma once
// Internal: the surface model. A Lambertian lobe plus a GGX microfacet lobe (Smith masking,
// Schlick Fresnel with F0 = albedo, i.e. a tinted metal-like lobe for gold paper and steel),
// mixed by the material's `specular` weight; sampled as a one-sample mixture of both lobes.
#include <cmath>

#include "render_medium.hpp"
#include "smokescan/scene/scene.hpp"

namespace smokescan {

/// An orthonormal frame around n.
struct Frame {
    Vec3 s, t, n;
    explicit Frame(const Vec3& nn) : n(nn)
    {
        const double sign = std::copysign(1.0, n.z());
        const double a = -1.0 / (sign + n.z()), b = n.x() * n.y() * a;
        s = Vec3(1.0 + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
        t = Vec3(b, sign + n.y() * n.y() * a, -n.y());
    }
    Vec3 toWorld(const Vec3& v) const { return v.x() * s + v.y() * t + v.z() * n; }
    Vec3 toLocal(const Vec3& v) const { return Vec3(v.dot(s), v.dot(t), v.dot(n)); }
};

inline Vec3 sampleCosineHemisphere(double u1, double u2)
{
    const double r = std::sqrt(u1), phi = 2 * M_PI * u2;
    return Vec3(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1.0 - u1)));
}

/// Henyey–Greenstein phase function p(cos θ) [1/sr], θ between propagation directions.
inline double hgPhase(double cos_theta, double g)
{
    const double d = 1 + g * g - 2 * g * cos_theta;
    return (1 - g * g) / (4 * M_PI * d * std::sqrt(d));
}

/// Samples a propagation direction after scattering of a photon travelling along `dir`.
inline Vec3 sampleHg(const Vec3& dir, double g, double u1, double u2)
{
    double cos_t;
    if (std::abs(g) < 1e-3) {
        cos_t = 1 - 2 * u1;
    } else {
        const double sq = (1 - g * g) / (1 - g + 2 * g * u1);
        cos_t = (1 + g * g - sq * sq) / (2 * g);
    }
    cos_t = std::clamp(cos_t, -1.0, 1.0);
    const double sin_t = std::sqrt(std::max(0.0, 1 - cos_t * cos_t)), phi = 2 * M_PI * u2;
    return Frame(dir).toWorld(Vec3(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t));
}

class Bsdf {
public:
    Bsdf(const Material& m, const Vec3& n)
        : frame_(n), albedo_(m.albedo.array()), spec_(m.specular), alpha_(std::max(1e-3, m.roughness * m.roughness))
    {
    }

    /// f(wo, wi) [1/sr], RGB; wo, wi point away from the surface.
    Rgb eval(const Vec3& wo_w, const Vec3& wi_w) const
    {
        const Vec3 wo = frame_.toLocal(wo_w), wi = frame_.toLocal(wi_w);
        if (wo.z() <= 0 || wi.z() <= 0) return Rgb::Zero();
        Rgb f = (1 - spec_) * albedo_ / M_PI;
        if (spec_ > 0) {
            const Vec3 h = (wo + wi).normalized();
            const double F5 = std::pow(1 - std::max(0.0, wi.dot(h)), 5);
            const Rgb F = albedo_ + (Rgb::Ones() - albedo_) * F5;
            f += spec_ * F * (D(h) * G1(wo) * G1(wi) / (4 * wo.z() * wi.z()));
        }
        return f;
    }
    double pdf(const Vec3& wo_w, const Vec3& wi_w) const
    {
        const Vec3 wo = frame_.toLocal(wo_w), wi = frame_.toLocal(wi_w);
        if (wo.z() <= 0 || wi.z() <= 0) return 0;
        double p = (1 - spec_) * wi.z() / M_PI;
        if (spec_ > 0) {
            const Vec3 h = (wo + wi).normalized();
            p += spec_ * D(h) * h.z() / (4 * wo.dot(h));
        }
        return p;
    }
    /// Samples wi; false when none. weight = f·cos/pdf.
    bool sample(const Vec3& wo_w, double u0, double u1, double u2, Vec3& wi_w, Rgb& weight) const
    {
        const Vec3 wo = frame_.toLocal(wo_w);
        if (wo.z() <= 0) return false;
        Vec3 wi;
        if (u0 < spec_) {
            // GGX: tan²θh = α² u / (1 − u)
            const double t2 = alpha_ * alpha_ * u1 / std::max(1e-12, 1 - u1), ct = 1 / std::sqrt(1 + t2),
                         st = std::sqrt(std::max(0.0, 1 - ct * ct)), phi = 2 * M_PI * u2;
            const Vec3 h(st * std::cos(phi), st * std::sin(phi), ct);
            wi = 2 * wo.dot(h) * h - wo;
        } else {
            wi = sampleCosineHemisphere(u1, u2);
        }
        if (wi.z() <= 0) return false;
        wi_w = frame_.toWorld(wi);
        const double p = pdf(wo_w, wi_w);
        if (!(p > 0)) return false;
        weight = eval(wo_w, wi_w) * wi.z() / p;
        return true;
    }

private:
    double D(const Vec3& h) const
    {
        const double a2 = alpha_ * alpha_, c2 = h.z() * h.z(), d = c2 * (a2 - 1) + 1;
        return a2 / (M_PI * d * d);
    }
    double G1(const Vec3& w) const
    {
        const double c2 = w.z() * w.z(), t2 = (1 - c2) / std::max(c2, 1e-12);
        return 2 / (1 + std::sqrt(1 + alpha_ * alpha_ * t2));
    }
    Frame frame_;
    Rgb albedo_;
    double spec_, alpha_;
};

}  // namespace smokescan
