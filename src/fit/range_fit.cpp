// Range bias and noise against saturation (the gold paper's growth): per beam, ranges relative to
// its clear-air median; binned by the saturation drop; straight lines fitted with Ceres.
#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>

#include "ceres_fit.hpp"
#include "smokescan/core/order_stats.hpp"
#include "smokescan/fit/sensor_fit.hpp"

namespace smokescan {
namespace {

struct LineResidual {
    double x, y, se;
    template <class T>
    bool operator()(const T* p, T* r) const
    {
        r[0] = (T(y) - (p[0] + p[1] * T(x))) / T(se);
        return true;
    }
};

struct Line {
    Estimate a, b;
    double chi2 = 0;
    bool ok = false;
};

/// y = a + b·x by weighted least squares with Ceres; covariance scaled by χ²/dof when above 1.
Line fitLine(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& se)
{
    double p[2] = {0, 0};
    ceres::Problem problem;
    for (size_t i = 0; i < x.size(); ++i)
        problem.AddResidualBlock(
            new ceres::AutoDiffCostFunction<LineResidual, 1, 2>(new LineResidual{x[i], y[i], se[i]}), nullptr, p);
    ceres::Solver::Options opt;
    opt.linear_solver_type = ceres::DENSE_QR;
    ceres::Solver::Summary sum;
    ceres::Solve(opt, &problem, &sum);
    Line l;
    l.chi2 = 2 * sum.final_cost;
    ceres::Covariance cov({});
    const std::vector<std::pair<const double*, const double*>> blocks = {{p, p}};
    if (!sum.IsSolutionUsable() || !cov.Compute(blocks, &problem)) return l;
    double c[4];
    cov.GetCovarianceBlock(p, p, c);
    const int dof = int(x.size()) - 2;
    const double scale = dof > 0 ? std::max(1.0, l.chi2 / dof) : 1.0;
    l.a = {p[0], std::sqrt(c[0] * scale)};
    l.b = {p[1], std::sqrt(c[3] * scale)};
    l.ok = true;
    return l;
}

}  // namespace

RangeFit fitRangeBiasNoise(const std::string& group, const std::vector<std::vector<double>>& range_m,
                           const std::vector<double>& S, double S_clear_min, const SensorFitConfig& cfg)
{
    RangeFit f;
    f.group = group;
    const size_t K = range_m.size(), B = K ? range_m.front().size() : 0;
    std::vector<double> clear_S;
    for (size_t k = 0; k < K; ++k)
        if (S[k] >= S_clear_min) clear_S.push_back(S[k]);
    f.S_ref = median(clear_S);
    std::vector<double> ref(B, NAN);
    for (size_t i = 0; i < B; ++i) {
        std::vector<double> r;
        for (size_t k = 0; k < K; ++k)
            if (S[k] >= S_clear_min && !std::isnan(range_m[k][i])) r.push_back(range_m[k][i]);
        if (r.size() >= 3) ref[i] = median(r);
    }
    // Observations (x = S_ref − S, d = range − the beam's clear-air median).
    std::vector<std::pair<double, double>> obs;
    for (size_t k = 0; k < K; ++k)
        if (!std::isnan(S[k]))
            for (size_t i = 0; i < B; ++i)
                if (!std::isnan(range_m[k][i]) && !std::isnan(ref[i]))
                    obs.emplace_back(f.S_ref - S[k], range_m[k][i] - ref[i]);
    f.observations = (long long)obs.size();
    if (obs.size() < 30) {
        f.diagnosis = "too few valid ranges with a clear-air reference (" + std::to_string(obs.size()) + ")";
        return f;
    }
    double x_lo = obs.front().first, x_hi = x_lo;
    for (const auto& o : obs) {
        x_lo = std::min(x_lo, o.first);
        x_hi = std::max(x_hi, o.first);
    }
    const int nb = std::max(3, cfg.range_bins);
    std::vector<std::vector<std::pair<double, double>>> bins(static_cast<size_t>(nb));
    for (const auto& o : obs) {
        const int b = x_hi > x_lo ? std::min(nb - 1, int((o.first - x_lo) / (x_hi - x_lo) * nb)) : 0;
        bins[size_t(b)].push_back(o);
    }
    std::vector<double> xs, mean, se_mean, sd, se_sd;
    for (const auto& b : bins) {
        if (b.size() < 10) continue;
        RangeFit::Bin r;
        r.n = int(b.size());
        double sx = 0, sy = 0;
        for (const auto& [x, d] : b) {
            sx += x;
            sy += d;
        }
        r.x = sx / r.n;
        r.S = f.S_ref - r.x;
        r.mean_m = sy / r.n;
        // The spread about the bin's own straight line: a bias growing across the bin is not noise.
        double sxx = 0, sxy = 0;
        for (const auto& [x, d] : b) {
            sxx += (x - r.x) * (x - r.x);
            sxy += (x - r.x) * (d - r.mean_m);
        }
        const double slope = sxx > 0 ? sxy / sxx : 0;
        double ss = 0;
        for (const auto& [x, d] : b) ss += std::pow(d - r.mean_m - slope * (x - r.x), 2);
        r.sd_m = std::sqrt(ss / (r.n - 2));
        // Floors keep a bin of identical (quantised) ranges from claiming infinite weight.
        r.se_mean_m = std::max(r.sd_m, 1e-4) / std::sqrt(double(r.n));
        r.se_sd_m = std::max(r.sd_m, 1e-4) / std::sqrt(2.0 * (r.n - 1));
        f.bins.push_back(r);
        xs.push_back(r.x);
        mean.push_back(r.mean_m);
        se_mean.push_back(r.se_mean_m);
        sd.push_back(r.sd_m);
        se_sd.push_back(r.se_sd_m);
    }
    if (f.bins.size() < 3) {
        f.diagnosis = "saturation varies too little among valid ranges to fit bias and noise against it";
        return f;
    }
    const Line b = fitLine(xs, mean, se_mean), n = fitLine(xs, sd, se_sd);
    if (!b.ok || !n.ok) {
        f.diagnosis = "the bias or noise fit failed";
        return f;
    }
    f.bias0 = b.a;
    f.bias_slope = b.b;
    f.noise0 = n.a;
    f.noise_slope = n.b;
    f.chi2_bias = b.chi2;
    f.chi2_noise = n.chi2;
    f.dof = int(xs.size()) - 2;
    f.fitted = true;
    return f;
}

}  // namespace smokescan
