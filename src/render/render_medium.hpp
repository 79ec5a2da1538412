#pragma once
// Internal: the scene's smoke as the renderer sees it at one time. RGB extinction per component
// (σ_t at 610, 550 and 465 nm from the medium's tabulated values) and a coarse world-space grid
// walked by DDA (empty cells skipped) holding, per cell, the majorant μ̄ for free flights and, for
// transmittance, a control extinction σ_c (from the cell's exact minimum density) with the residual
// majorant μ̄_r ≥ σ_t − σ_c. Free flights: spectral tracking. Transmittance: residual ratio
// tracking (Novák et al. 2014) — exact and free in homogeneous cells, where plain ratio tracking
// with a tight majorant degenerates into a 0/1 estimator.
#include <Eigen/Core>
#include <vector>

#include "smokescan/core/random.hpp"
#include "smokescan/media/smoke.hpp"

namespace smokescan {

using Rgb = Eigen::Array3d;

/// Wavelengths [nm] the renderer's R, G, B channels stand for.
constexpr double kRgbWavelengths[3] = {610.0, 550.0, 465.0};

struct MediumEvent {
    enum Kind { Escape, Scatter, Absorb } kind = Escape;
    double t = kInf;
    double g = 0;  ///< HG asymmetry of the component that scattered
};

class RenderMedium {
public:
    /// A VDB grid, or (grid null) an analytic homogeneous box of density 1 — the reference the
    /// grid path is tested against.
    struct Component {
        std::shared_ptr<const DensityGrid> grid;
        Aabb box;  ///< analytic component only
        double scale = 1;
        Rgb sigma_t = Rgb::Zero();  ///< per unit density [1/m]
        double albedo = 1, g = 0;
    };

    RenderMedium() = default;
    /// @param cells_per_axis resolution of the majorant grid along its longest axis
    RenderMedium(const SmokeField& field, int cells_per_axis = 64);
    explicit RenderMedium(std::vector<Component> comps, int cells_per_axis = 64);

    bool empty() const { return comps_.empty(); }

    /// The part [t0, t1) of [0, t_max) inside the smoke's bounds; false when there is none.
    bool clip(const Ray& ray, double t_max, double& t0, double& t1) const
    {
        t0 = 0;
        t1 = t_max;
        return !comps_.empty() && bounds_.clip(ray, t0, t1) && t1 > t0;
    }

    /// σ_t(x) and σ_s(x) [1/m], RGB.
    void coefficients(const Vec3& p, Rgb& sigma_t, Rgb& sigma_s) const;

    /// @brief Free-flight sampling along [0, t_max) by spectral tracking (Kutz et al. 2017):
    /// one scalar majorant for all channels; at each tentative collision an absorption, scattering
    /// or null event is chosen with probabilities from the throughput-weighted coefficients, and
    /// `beta` is reweighted per channel by σ_x/(μ̄·P_x), so every channel stays unbiased.
    MediumEvent sample(const Ray& ray, double t_max, Rgb& beta, KeyedRng& rng) const;

    /// @brief Transmittance over [0, t_max) by residual ratio tracking (unbiased, per channel).
    Rgb transmittance(const Ray& ray, double t_max, KeyedRng& rng) const;

    /// @brief A distance in [0, t_max) drawn from the majorant's free-flight density truncated to
    /// the segment, p(t) = μ̄(t)·e^{−τ̄(t)} / (1 − e^{−τ̄(t_max)}) (a forced collision: in a
    /// homogeneous cell it is the exact σ_t·T density). False when the majorant is zero along it.
    bool sampleForced(const Ray& ray, double t_max, double u, double& t, double& pdf) const;

    /// @brief The density of sampleForced at t [1/m] (0 where the majorant is zero).
    double forcedPdf(const Ray& ray, double t_max, double t) const;

    /// Calls f(σ_s RGB [1/m], HG g) for each component with smoke at p: the phase function at p
    /// is the σ_s-weighted mixture, per channel.
    template <class F>
    void forEachScatterer(const Vec3& p, F&& f) const
    {
        for (const auto& c : comps_) {
            const double rho = density(c, p) * c.scale;
            if (rho > 0) f(Rgb(rho * c.albedo * c.sigma_t), c.g);
        }
    }

    /// Walks majorant cells: f(t0, t1, cell) returns true to stop.
    template <class F>
    void walkMajorant(const Ray& ray, double t_max, F&& f) const;

private:
    void build(int cells_per_axis);
    static double density(const Component& c, const Vec3& p);

    std::vector<Component> comps_;
    Aabb bounds_;
    Vec3 cell_m_ = Vec3::Ones();
    int n_[3] = {0, 0, 0};
    struct Cell {
        float mu = 0;  ///< majorant of the max-channel σ_t [1/m]
        float mu_r = 0;  ///< residual majorant ≥ |σ_t − σ_c| [1/m]
        float ctrl[3] = {0, 0, 0};  ///< control extinction σ_c, RGB [1/m]
    };
    std::vector<Cell> cells_;
};

template <class F>
void RenderMedium::walkMajorant(const Ray& ray, double t_max, F&& f) const
{
    double t0 = 0, t1 = t_max;
    if (comps_.empty() || !bounds_.clip(ray, t0, t1) || !(t1 > t0)) return;
    int c[3], step[3];
    double tn[3], dt[3];
    for (int a = 0; a < 3; ++a) {
        const double x = (ray.o[a] + ray.d[a] * t0 - bounds_.lo[a]) / cell_m_[a];
        c[a] = std::clamp(int(std::floor(x)), 0, n_[a] - 1);
        step[a] = ray.d[a] >= 0 ? 1 : -1;
        if (ray.d[a] == 0) {
            tn[a] = dt[a] = kInf;
        } else {
            const double bound = bounds_.lo[a] + (c[a] + (step[a] > 0 ? 1 : 0)) * cell_m_[a];
            tn[a] = (bound - ray.o[a]) / ray.d[a];
            dt[a] = cell_m_[a] / std::abs(ray.d[a]);
        }
    }
    double t = t0;
    while (t < t1) {
        const int a = tn[1] < tn[0] ? (tn[2] < tn[1] ? 2 : 1) : (tn[2] < tn[0] ? 2 : 0);
        const double te = std::min(tn[a], t1);
        if (te > t && f(t, te, cells_[(size_t(c[2]) * n_[1] + c[1]) * n_[0] + c[0]])) return;
        t = std::max(t, te);
        c[a] += step[a];
        if (c[a] < 0 || c[a] >= n_[a]) return;
        tn[a] += dt[a];
    }
}

}  // namespace smokescan
