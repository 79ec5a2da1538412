// The renderer's surface model (src/render/bsdf.hpp: Lambert + GGX with Smith masking and Schlick
// Fresnel) against what any physically based BSDF must satisfy: reciprocity, no more energy out
// than in, a normalised microfacet distribution, and a sampler whose directions follow its pdf.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "render/bsdf.hpp"
#include "smokescan/core/random.hpp"

using namespace smokescan;

namespace {

Material material(double albedo, double specular, double roughness)
{
    Material m;
    m.albedo = Vec3::Constant(albedo);
    m.specular = specular;
    m.roughness = roughness;
    return m;
}

Vec3 direction(double theta, double phi)
{
    return Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
}

/// ∫ over the upper hemisphere of g(ω) dω by the midpoint rule in (cos θ, φ).
template <class F>
double hemisphere(F g, int n_mu = 400, int n_phi = 200)
{
    double s = 0;
    for (int i = 0; i < n_mu; ++i)
        for (int j = 0; j < n_phi; ++j) {
            const double mu = (i + 0.5) / n_mu, phi = 2 * M_PI * (j + 0.5) / n_phi;
            s += g(direction(std::acos(mu), phi));
        }
    return s * (2 * M_PI) / (double(n_mu) * n_phi);
}

const Vec3 kNormal(0, 0, 1);

}  // namespace

TEST(Bsdf, IsReciprocal)
{
    // f(wo, wi) = f(wi, wo) for every mix of the lobes, roughness and colour.
    KeyedRng rng(1, 2);
    for (double spec : {0.0, 0.3, 1.0})
        for (double rough : {0.1, 0.5, 0.9}) {
            Material m = material(0.7, spec, rough);
            m.albedo = Vec3(0.9, 0.5, 0.2);
            const Bsdf f(m, kNormal);
            for (int k = 0; k < 200; ++k) {
                const Vec3 a = direction(std::acos(rng.uniform()), 2 * M_PI * rng.uniform());
                const Vec3 b = direction(std::acos(rng.uniform()), 2 * M_PI * rng.uniform());
                const Rgb ab = f.eval(a, b), ba = f.eval(b, a);
                for (int c = 0; c < 3; ++c) EXPECT_NEAR(ab[c], ba[c], 1e-12 * std::max(1.0, ab[c]));
            }
        }
}

TEST(Bsdf, GgxDistributionIsNormalisedOverProjectedArea)
{
    // ∫ D(h) cos θh dωh = 1 (the microfacets' projected area is the surface's), seen through the
    // pure GGX lobe's sampling pdf at normal incidence: pdf(wi) = D(h)·cos θh / (4 wo·h) with
    // dωi = 4 (wo·h) dωh, and wi = 2θh stays above the horizon for θh < 45°. So the pdf over the
    // upper hemisphere is GGX's share of half-vectors within 45°: P(tan²θh < 1) = 1 / (1 + α²),
    // α = roughness², the distribution's closed-form CDF.
    for (double rough : {0.3, 0.5, 0.7, 0.9}) {
        const Bsdf f(material(1.0, 1.0, rough), kNormal);
        const double alpha = rough * rough;
        const double total = hemisphere([&](const Vec3& wi) { return f.pdf(kNormal, wi); }, 4000, 32);
        EXPECT_NEAR(total, 1 / (1 + alpha * alpha), 1e-3) << "roughness " << rough;
    }
}

TEST(Bsdf, ReflectsNoMoreEnergyThanArrives)
{
    // The directional albedo ∫ f(wo, wi) cos θi dωi of a white surface (albedo 1): exactly 1 for
    // Lambert, at most 1 for GGX (single-scattering Smith loses what is masked and what microfacets
    // send below the horizon), close to 1 for a smooth lobe at normal incidence, and falling there
    // as roughness grows. By quadrature and, independently, by the sampler's mean weight.
    auto albedo = [](const Bsdf& f, const Vec3& wo) {
        return hemisphere([&](const Vec3& wi) { return f.eval(wo, wi)[0] * wi.z(); }, 1000, 200);
    };
    const Bsdf lambert(material(1.0, 0.0, 0.5), kNormal);
    EXPECT_NEAR(albedo(lambert, direction(0.7, 0.3)), 1.0, 1e-6);
    double last_rough = 2;
    for (double rough : {0.3, 0.5, 0.8}) {
        const Bsdf f(material(1.0, 1.0, rough), kNormal);
        for (double theta : {0.0, 0.6, 1.2, 1.45}) {
            const Vec3 wo = direction(theta, 0.4);
            const double a = albedo(f, wo);
            EXPECT_LE(a, 1.0 + 2e-3) << "roughness " << rough << " theta " << theta;
            // The sampler's mean weight f·cos/pdf over every draw (a failed draw counts 0).
            KeyedRng rng(3, uint64_t(100 * rough), uint64_t(100 * theta));
            const int n = 200000;
            double s = 0, s2 = 0;
            for (int k = 0; k < n; ++k) {
                Vec3 wi;
                Rgb w;
                const double x = f.sample(wo, rng.uniform(), rng.uniform(), rng.uniform(), wi, w) ? w[0] : 0.0;
                s += x;
                s2 += x * x;
            }
            const double mean = s / n, se = std::sqrt(std::max(0.0, s2 / n - mean * mean) / n);
            EXPECT_NEAR(mean, a, 4 * se + 2e-3) << "roughness " << rough << " theta " << theta;
        }
        const double normal = albedo(f, kNormal);
        EXPECT_LT(normal, last_rough + 1e-6);
        last_rough = normal;
        if (rough <= 0.3) EXPECT_GT(normal, 0.97) << "little is masked at normal incidence on a smooth lobe";
    }
}

TEST(Bsdf, SampledDirectionsFollowThePdf)
{
    // Pearson's χ² of the sampler's directions in (cos θ, φ) cells against the pdf integrated over
    // each cell, for the mixture and each lobe, at normal and oblique incidence: a sampler and a
    // pdf that disagree (a missing Jacobian, a wrong mixture weight) fail it.
    const int n_mu = 10, n_phi = 12, n = 400000;
    for (double spec : {0.0, 0.5, 1.0})
        for (double theta : {0.2, 1.0}) {
            const Bsdf f(material(0.8, spec, 0.4), kNormal);
            const Vec3 wo = direction(theta, 0.0);
            std::vector<double> expected(n_mu * n_phi, 0.0), seen(n_mu * n_phi, 0.0);
            const int sub = 24;  // quadrature points per cell side
            for (int i = 0; i < n_mu * sub; ++i)
                for (int j = 0; j < n_phi * sub; ++j) {
                    const double mu = (i + 0.5) / (n_mu * sub), phi = 2 * M_PI * (j + 0.5) / (n_phi * sub);
                    expected[size_t((i / sub) * n_phi + j / sub)] +=
                        f.pdf(wo, direction(std::acos(mu), phi)) * 2 * M_PI / (double(n_mu * sub) * n_phi * sub) * n;
                }
            KeyedRng rng(5, uint64_t(10 * spec), uint64_t(10 * theta));
            for (int k = 0; k < n; ++k) {
                Vec3 wi;
                Rgb w;
                if (!f.sample(wo, rng.uniform(), rng.uniform(), rng.uniform(), wi, w)) continue;
                const int i = std::min(n_mu - 1, int(wi.z() * n_mu));
                double phi = std::atan2(wi.y(), wi.x());
                if (phi < 0) phi += 2 * M_PI;
                const int j = std::min(n_phi - 1, int(phi / (2 * M_PI) * n_phi));
                seen[size_t(i * n_phi + j)] += 1;
            }
            double chi2 = 0;
            int cells = 0;
            for (size_t c = 0; c < seen.size(); ++c) {
                if (expected[c] < 5) continue;
                chi2 += (seen[c] - expected[c]) * (seen[c] - expected[c]) / expected[c];
                ++cells;
            }
            // χ² with about `cells` dof: mean k, sd √(2k); 5 sd above the mean is far in the tail.
            EXPECT_LT(chi2, cells + 5 * std::sqrt(2.0 * cells))
                << "specular " << spec << " theta " << theta << ": chi2 " << chi2 << " on " << cells << " cells";
        }
}
