#include "smokescan/media/plume.hpp"

#include <cmath>

#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/core/random.hpp"

namespace smokescan {

void PlumeConfig::validate() const
{
    auto pos = [](double v, const char* name) {
        if (!(v > 0) || !std::isfinite(v)) throw Error("", std::string(name) + " must be finite and > 0");
    };
    auto nonneg = [](double v, const char* name) {
        if (!(v >= 0) || !std::isfinite(v)) throw Error("", std::string(name) + " must be finite and >= 0");
    };
    pos(rate_per_s, "rate_per_s");
    pos(lifetime_s, "lifetime_s");
    pos(radius_m, "radius_m");
    pos(peak_density, "peak_density");
    pos(voxel_m, "voxel_m");
    nonneg(spread_m_s, "spread_m_s");
    nonneg(growth_m_s, "growth_m_s");
    if (!std::isfinite(rise_m_s)) throw Error("", "rise_m_s must be finite");
    if (!source_m.allFinite() || !wind_m_s.allFinite()) throw Error("", "source_m and wind_m_s must be finite");
    if (!std::isfinite(start_s) || !(stop_s > start_s)) throw Error("", "plume needs a finite start_s < stop_s");
    if (rate_per_s * lifetime_s > 2e5)
        throw Error("", "plume has more than 200000 live particles (rate_per_s × lifetime_s)");
    // Bounded work: each live puff is rasterised over a cube of 6σ a side (σ up to radius_m +
    // growth_m_s·lifetime_s), and its voxel indices must fit the grid's integer coordinates.
    const double sigma_max = radius_m + growth_m_s * lifetime_s;
    if (voxelBound() > limits::kPlumeVoxels)
        throw Error("",
                    "plume puffs would cover about " + limits::count(voxelBound()) +
                        " voxels at once (at most 5e8): raise voxel or lower radius_m, growth_m_s or rate_per_s");
    const double reach =
        source_m.norm() + (wind_m_s.norm() + std::abs(rise_m_s) + 8 * spread_m_s) * lifetime_s + 3 * sigma_max;
    if (reach / voxel_m > 1e8)
        throw Error("", "plume reaches " + std::to_string(reach) + " m from the origin, over 1e8 voxels");
}

double PlumeConfig::voxelBound() const
{
    const double sigma_max = radius_m + growth_m_s * lifetime_s;
    const double side = 6 * sigma_max / voxel_m + 2, live = std::ceil(rate_per_s * lifetime_s) + 1;
    return live * side * side * side;
}

std::vector<DensityGrid::Blob> plumeBlobs(const PlumeConfig& c, double t)
{
    std::vector<DensityGrid::Blob> blobs;
    if (t < c.start_s) return blobs;
    // Particles alive at t were born in (t − lifetime, min(t, stop)].
    const double born_hi = std::min(t, c.stop_s), born_lo = t - c.lifetime_s;
    const double dk_hi = std::floor((born_hi - c.start_s) * c.rate_per_s),
                 dk_lo = std::floor((born_lo - c.start_s) * c.rate_per_s);
    if (!(dk_hi < 1e15))
        throw Error("", "plume time " + std::to_string(t) + " s is too far after start_s for its particle count");
    const long long k_hi = (long long)dk_hi, k_lo = std::max(0LL, (long long)std::max(dk_lo, -1.0));
    for (long long k = k_lo; k <= k_hi; ++k) {
        const double birth = c.start_s + double(k) / c.rate_per_s;
        const double age = t - birth;
        if (age < 0 || age >= c.lifetime_s || birth > c.stop_s) continue;
        KeyedRng rng(c.seed, uint64_t(k), 0x706c756dull);
        // Drawn z, y, x, one statement each: as arguments of one call their order was the
        // compiler's (gcc's right to left), and clang's builds made other plumes.
        const double vz = rng.normal();
        const double vy = rng.normal();
        const double vx = rng.normal();
        const Vec3 v_own(vx, vy, vz);
        const Vec3 vel = c.wind_m_s + Vec3(0, 0, c.rise_m_s) + c.spread_m_s * v_own;
        const double sigma = c.radius_m + c.growth_m_s * age;
        // Mass conserved while the puff grows; a smooth fade over the last fifth of its life.
        const double x = age / c.lifetime_s;
        const double fade = x < 0.8 ? 1.0 : 0.5 * (1.0 + std::cos(M_PI * (x - 0.8) / 0.2));
        const double peak = c.peak_density * std::pow(c.radius_m / sigma, 3) * fade;
        blobs.push_back({c.source_m + vel * age, sigma, peak});
    }
    return blobs;
}

DensityGrid rasterisePlume(const PlumeConfig& cfg, double t)
{
    cfg.validate();
    return DensityGrid::fromBlobs(plumeBlobs(cfg, t), cfg.voxel_m);
}

}  // namespace smokescan
