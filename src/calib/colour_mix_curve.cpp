#include "smokescan/calib/colour_mix_curve.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>

#include "ceres_fit.hpp"
#include "smokescan/core/error.hpp"

namespace smokescan {
namespace {

template <class T>
T max3(const T& a, const T& b, const T& c)
{
    const T m = a > b ? a : b;
    return m > c ? m : c;
}
template <class T>
T min3(const T& a, const T& b, const T& c)
{
    const T m = a < b ? a : b;
    return m < c ? m : c;
}

/// The scattered light's colour at density rho: thin = (A_G, A_B) of thin smoke's light (A_R = 1),
/// drift = (s, D_G, D_B, kappa): w·(1, A_G, A_B) + (1 − w)·s·(1, D_G, D_B), w = e^{−kappa·rho}
/// (kappa = 0: one colour at every density).
template <class T>
void airlightAt(double rho, const T* thin, const T* drift, T* a)
{
    using std::exp;
    const T w = exp(-drift[3] * rho), one(1.0), v = (one - w) * drift[0];
    a[0] = w + v;
    a[1] = w * thin[0] + v * drift[1];
    a[2] = w * thin[1] + v * drift[2];
}

/// Noise-free saturation of a patch of colour l under the light `air` (thin, then drift) at
/// transmittance e^{−bρ}.
template <class T>
T cleanSaturation(double rho, const T& b, const T* air, const T* l, double gamma)
{
    using std::exp;
    using std::pow;
    const T tr = exp(-b * rho), one(1.0);
    T a[3];
    airlightAt(rho, air, air + 2, a);
    const T r = l[0] * tr + a[0] * (one - tr), g = l[1] * tr + a[1] * (one - tr), bl = l[2] * tr + a[2] * (one - tr);
    return one - pow(min3(r, g, bl) / max3(r, g, bl), T(gamma));
}

/// Mean and second moment of max(X1, X2) for independent normals (Clark 1961, exact).
template <class T>
void clarkMax(const T& m1, const T& v1, const T& m2, const T& v2, T& mean, T& var)
{
    using std::erf;
    using std::exp;
    using std::sqrt;
    const T theta = sqrt(v1 + v2), a = (m1 - m2) / theta;
    const T Pa = 0.5 * (1.0 + erf(a / std::sqrt(2.0))), Pb = 1.0 - Pa;
    const T pa = exp(-0.5 * a * a) / std::sqrt(2 * M_PI);
    mean = m1 * Pa + m2 * Pb + theta * pa;
    const T second = (m1 * m1 + v1) * Pa + (m2 * m2 + v2) * Pb + (m1 + m2) * theta * pa;
    var = second - mean * mean;
    if (var < T(1e-30)) var = T(1e-30);
}

/// E[max] of three independent normals of means y and common sd s: Clark's moments, max(X1, X2)
/// taken as normal for its max with X3 (exact for two; 0.2 % high on the range of three iid).
template <class T>
T expectedMax3(const T* y, const T& s)
{
    T m, v;
    clarkMax(y[0], s * s, y[1], s * s, m, v);
    T m3, v3;
    clarkMax(m, v, y[2], s * s, m3, v3);
    return m3;
}

/// The patch's mean saturation as the camera measures it: over the patch's brightness classes
/// (pixel luminance / patch mean, measured in clear air: the lamp lights the patch unevenly, so
/// the scattered light's share differs from pixel to pixel), the expected saturation under
/// independent normal noise on the three encoded channels of relative sd s_rel (from the measured
/// floor f: s_rel = f·√π/3), as 1 − E[min]/E[max] (the ratio's own noise is second order in s_rel).
template <class T>
T patchSaturation(double rho, const T& b, const T* thin, const T* drift, const T* l, const std::vector<double>& classes,
                  double s_rel, double gamma)
{
    using std::exp;
    using std::pow;
    const T tr = exp(-b * rho), one(1.0);
    T a[3];
    airlightAt(rho, thin, drift, a);
    T total(0.0);
    for (double k : classes) {
        const T x[3] = {k * l[0] * tr + a[0] * (one - tr), k * l[1] * tr + a[1] * (one - tr),
                        k * l[2] * tr + a[2] * (one - tr)};
        const T y[3] = {pow(x[0], T(gamma)), pow(x[1], T(gamma)), pow(x[2], T(gamma))};
        if (!(s_rel > 0)) {
            total += one - min3(y[0], y[1], y[2]) / max3(y[0], y[1], y[2]);
            continue;
        }
        const T sd = s_rel * (y[0] + y[1] + y[2]) / 3.0;
        const T neg[3] = {-y[0], -y[1], -y[2]};
        total += one - (-expectedMax3(neg, sd)) / expectedMax3(y, sd);
    }
    return total / double(classes.size());
}

/// One point's residual in units of its standard error.
struct MixResidual {
    double rho, S, sigma, floor, gamma;
    const std::vector<double>* classes;
    template <class T>
    bool operator()(const T* const b, const T* const thin, const T* const drift, const T* const l, T* r) const
    {
        const T m = patchSaturation(rho, b[0], thin, drift, l, *classes, floor * std::sqrt(M_PI) / 3, gamma);
        r[0] = (m - T(S)) / T(sigma);
        return true;
    }
};

}  // namespace

double ColourMixCurve::clean(size_t p, double rho) const
{
    const std::array<double, 6> air = packedAirlight();
    return cleanSaturation(rho, b, air.data(), target[p].data(), gamma);
}

double ColourMixCurve::floorAt(size_t p, double rho) const
{
    const auto& f = floor[p];
    const auto& d = floor_density;
    if (d.empty()) return 0.0;
    if (rho <= d.front()) return f.front();
    for (size_t i = 1; i < d.size(); ++i)
        if (rho <= d[i]) return f[i - 1] + (f[i] - f[i - 1]) * (rho - d[i - 1]) / (d[i] - d[i - 1]);
    return f.back();
}

double ColourMixCurve::patch(size_t p, double rho) const
{
    const std::array<double, 6> air = packedAirlight();
    return patchSaturation(rho, b, air.data(), air.data() + 2, target[p].data(), brightness[p],
                           floorAt(p, rho) * std::sqrt(M_PI) / 3, gamma);
}

std::array<double, 6> ColourMixCurve::packedAirlight() const
{
    const double s = airlight_dense[0];
    return {{airlight[1], airlight[2], s, airlight_dense[1] / s, airlight_dense[2] / s, kappa}};
}

std::array<double, 3> ColourMixCurve::airlightAt(double rho) const
{
    const std::array<double, 6> air = packedAirlight();
    std::array<double, 3> a{};
    smokescan::airlightAt(rho, air.data(), air.data() + 2, a.data());
    return a;
}

double ColourMixCurve::combined(double rho) const
{
    double s = 0, w = 0;
    for (size_t p = 0; p < target.size(); ++p) {
        s += weight[p] * patch(p, rho);
        w += weight[p];
    }
    return w > 0 ? s / w : 0.0;
}

namespace {
/// ρ where the combined curve first falls to S on [0, rho_max] (bisection on the first crossing).
double firstCrossing(const ColourMixCurve& c, double S, double rho_max)
{
    const int n = 400;
    double lo = 0;
    if (!(c.combined(0) > S))
        throw Error("", "saturation " + std::to_string(S) + " is at or above the clear-air value");
    for (int i = 1; i <= n; ++i) {
        double hi = rho_max * i / n;
        if (c.combined(hi) <= S) {
            for (int k = 0; k < 60; ++k) {
                const double mid = 0.5 * (lo + hi);
                (c.combined(mid) > S ? lo : hi) = mid;
            }
            return 0.5 * (lo + hi);
        }
        lo = hi;
    }
    throw Error("", "saturation " + std::to_string(S) + " is not reached below density " + std::to_string(rho_max));
}

constexpr size_t kAir = 6;  ///< the light's parameters: thin (2), drift (4)
constexpr size_t kL0 = 1 + kAir;  ///< where the patches' colours start in the packed vector

std::vector<double> packParams(const ColourMixCurve& c)
{
    std::vector<double> v = {c.b};
    const std::array<double, kAir> air = c.packedAirlight();
    v.insert(v.end(), air.begin(), air.end());
    for (const auto& l : c.target) v.insert(v.end(), l.begin(), l.end());
    return v;
}

ColourMixCurve unpackParams(ColourMixCurve c, const std::vector<double>& v)
{
    c.b = v[0];
    c.airlight = {{1.0, v[1], v[2]}};
    c.airlight_dense = {{v[3], v[3] * v[4], v[3] * v[5]}};
    c.kappa = v[6];
    for (size_t p = 0; p < c.target.size(); ++p)
        for (int k = 0; k < 3; ++k) c.target[p][size_t(k)] = v[kL0 + 3 * p + size_t(k)];
    return c;
}
}  // namespace

std::pair<double, double> ColourMixFit::invert(double S, double rho_max) const
{
    const double rho = firstCrossing(curve, S, rho_max);
    const std::vector<double> v = packParams(curve);
    Eigen::VectorXd g(long(v.size()));
    for (size_t k = 0; k < v.size(); ++k) {
        std::vector<double> up = v, dn = v;
        const double h = 1e-5 * std::max(1e-3, std::abs(v[k]));
        up[k] += h;
        dn[k] -= h;
        g[long(k)] = (firstCrossing(unpackParams(curve, up), S, 2 * rho_max) -
                      firstCrossing(unpackParams(curve, dn), S, 2 * rho_max)) /
            (2 * h);
    }
    const double var = covariance.rows() == g.size() ? g.dot(covariance * g) : 0.0;
    return {rho, std::sqrt(std::max(0.0, var))};
}

ColourMixFit fitColourMix(const std::vector<PatchPoints>& patches, double gamma, bool drifting_light,
                          const ColourMixCurve* held_light)
{
    // Free parameters: b, thin smoke's light (2), its drift (4) if asked, 3 per patch; the light's
    // six none when it is held.
    if (held_light) drifting_light = held_light->kappa > 0;
    const size_t n_free = (held_light ? 1 : 3 + (drifting_light ? 4 : 0)) + 3 * patches.size();
    if (patches.empty()) throw Error("calibration", "no patches to fit");
    ColourMixCurve curve;
    curve.gamma = gamma;
    for (const auto& pp : patches) {
        if (pp.points.size() < 6 || pp.floor.size() != pp.points.size())
            throw Error("calibration", "patch '" + pp.name + "' needs at least 6 points, each with its noise floor");
        for (const auto& q : pp.points)
            if (!std::isfinite(q.density) || !std::isfinite(q.saturation) || !(q.sigma > 0) || q.density < 0)
                throw Error("calibration", "patch '" + pp.name + "' has a bad point");
        curve.names.push_back(pp.name);
        curve.weight.push_back(pp.weight);
        const double mx = std::max({pp.clear_colour[0], pp.clear_colour[1], pp.clear_colour[2], 1e-9});
        auto start = [&](int c) {
            return std::clamp(pp.clear_colour[size_t(c)] / mx, 1e-3, 1.0);
        };  // inside the bounds
        curve.target.push_back({{start(0), start(1), start(2)}});
        std::vector<double> f;
        curve.floor.push_back(pp.floor);
        std::vector<double> classes = pp.brightness.empty() ? std::vector<double>{1.0} : pp.brightness;
        for (double& k : classes)
            if (!(k >= 1e-3)) k = 1e-3;  // a black pixel has no colour to mix
        curve.brightness.push_back(classes);
    }
    for (const auto& q : patches[0].points) curve.floor_density.push_back(q.density);
    size_t n_points = 0;
    for (const auto& pp : patches) n_points += pp.points.size();
    if (n_points <= n_free)
        throw Error("calibration",
                    std::to_string(n_points) + " points cannot fit the colour-mixing curve's " +
                        std::to_string(n_free) + " parameters");

    ColourMixFit best;
    best.chi2 = 1e300;
    std::string last_message;
    // min/max make the cost rugged: three starts. The drifting light starts from the one-light
    // fit (no drift yet: the dense light equal to the thin one), and from the three if that fails.
    std::vector<std::vector<double>> starts;
    for (double b0 : {150.0, 300.0, 600.0}) {
        std::vector<double> v = packParams(curve);
        v[0] = b0;
        v[1] = v[2] = 0.9;  // thin smoke's light: warm
        v[3] = v[4] = v[5] = 1.0;  // dense smoke's: grey, as bright
        v[6] = drifting_light ? b0 : 0.0;  // kappa = 0: one colour throughout
        if (held_light) {
            const std::array<double, kAir> air = held_light->packedAirlight();
            std::copy(air.begin(), air.end(), v.begin() + 1);
        }
        starts.push_back(v);
    }
    if (drifting_light && !held_light) {
        const ColourMixFit one = fitColourMix(patches, gamma, false);
        if (!one.std_error.empty()) {
            std::vector<double> v = packParams(one.curve);
            v[3] = 1.0;
            v[4] = one.curve.airlight[1];
            v[5] = one.curve.airlight[2];
            v[6] = one.curve.b;
            starts.insert(starts.begin(), v);
        }
    }
    for (size_t start = 0; start < starts.size(); ++start) {
        if (drifting_light && !held_light && start > 0 && starts.size() > 3 && best.converged) break;
        std::vector<double> v = starts[start];
        ceres::Problem problem;
        for (size_t p = 0; p < patches.size(); ++p)
            for (size_t i = 0; i < patches[p].points.size(); ++i) {
                const auto& q = patches[p].points[i];
                problem.AddResidualBlock(
                    new ceres::AutoDiffCostFunction<MixResidual, 1, 1, 2, 4, 3>(new MixResidual{
                        q.density, q.saturation, q.sigma, patches[p].floor[i], gamma, &curve.brightness[p]}),
                    nullptr, &v[0], &v[1], &v[3], &v[kL0 + 3 * p]);
            }
        for (size_t k = 0; k < v.size(); ++k) {
            if (!drifting_light && k >= 3 && k < kL0) continue;
            double* block = k == 0 ? &v[0] : k < 3 ? &v[1] : k < kL0 ? &v[3] : &v[kL0 + 3 * ((k - kL0) / 3)];
            const int idx = k == 0 ? 0 : k < 3 ? int(k - 1) : k < kL0 ? int(k - 3) : int((k - kL0) % 3);
            problem.SetParameterLowerBound(block, idx, 1e-6);
            problem.SetParameterUpperBound(block, idx, k == 0 || k == 6 ? 1e5 : 1e3);
        }
        if (!drifting_light || held_light) problem.SetParameterBlockConstant(&v[3]);
        if (held_light) problem.SetParameterBlockConstant(&v[1]);
        ceres::Solver::Options opt;
        opt.linear_solver_type = ceres::DENSE_QR;
        opt.max_num_iterations = drifting_light ? 10000 : 2000;
        opt.function_tolerance = 1e-9;
        opt.parameter_tolerance = 1e-10;
        opt.logging_type = ceres::SILENT;
        ceres::Solver::Summary summary;
        const bool ok = detail::solveQuiet(problem, opt, summary) || detail::stalledAtMinimum(summary);
        last_message = summary.message;
        if (!summary.IsSolutionUsable() || !(summary.final_cost >= 0) || !(2 * summary.final_cost < best.chi2))
            continue;
        best = ColourMixFit{};
        best.curve = unpackParams(curve, v);
        best.chi2 = 2 * summary.final_cost;
        best.converged = ok;
        best.message = summary.BriefReport();
        // Covariance of every parameter, in the packed order.
        ceres::Covariance::Options copt;
        copt.algorithm_type = ceres::DENSE_SVD;
        copt.null_space_rank = -1;
        ceres::Covariance cov(copt);
        std::vector<const double*> blocks = {&v[0]};
        std::vector<long> at = {0};  // where each free parameter sits in the packed order
        if (!held_light) {
            blocks.push_back(&v[1]);
            at.insert(at.end(), {1, 2});
        }
        if (drifting_light && !held_light) {
            blocks.push_back(&v[3]);
            at.insert(at.end(), {3, 4, 5, 6});
        }
        for (size_t p = 0; p < patches.size(); ++p) {
            blocks.push_back(&v[kL0 + 3 * p]);
            for (long k = 0; k < 3; ++k) at.push_back(long(kL0 + 3 * p) + k);
        }
        best.covariance = Eigen::MatrixXd::Zero(long(v.size()), long(v.size()));
        // The covariance's SVD needs a finite Jacobian (Eigen's SVD fails on one that is not).
        ceres::CRSMatrix jac;
        double cost = 0;
        const bool finite = problem.Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr, nullptr, &jac) &&
            std::all_of(jac.values.begin(), jac.values.end(), [](double x) { return std::isfinite(x); });
        if (finite && cov.Compute(blocks, &problem)) {
            const long n_at = long(at.size());
            Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> C(n_at, n_at);
            if (cov.GetCovarianceMatrix(blocks, C.data()))
                for (long i = 0; i < n_at; ++i)
                    for (long j = 0; j < n_at; ++j) best.covariance(at[size_t(i)], at[size_t(j)]) = C(i, j);
        } else {
            best.converged = false;
            best.message += " (covariance could not be computed)";
        }
    }
    if (!(best.chi2 < 1e300)) {
        best = ColourMixFit{};
        best.curve = curve;
        best.message = "no start converged: " + last_message;
        return best;
    }
    size_t n = 0;
    best.patch_chi2.assign(patches.size(), 0.0);
    for (size_t p = 0; p < patches.size(); ++p)
        for (const auto& q : patches[p].points) {
            const double r = (best.curve.patch(p, q.density) - q.saturation) / q.sigma;
            best.patch_chi2[p] += r * r;
            ++n;
        }
    best.dof = int(n) - int(n_free);
    best.std_error.clear();
    for (long k = 0; k < best.covariance.rows(); ++k)
        best.std_error.push_back(std::sqrt(std::max(0.0, best.covariance(k, k))));
    return best;
}

namespace {
/// P(χ²_k > x) for an integer k ≥ 1: the regularised upper gamma function Q(k/2, x/2) in closed
/// form (a finite sum for even k; erfc plus a finite sum for odd k).
double chi2Survival(double x, int k)
{
    const double y = 0.5 * std::max(0.0, x);
    double q = 0, term = 0;
    if (k % 2 == 0) {
        term = 1;  // y^i / i!
        for (int i = 0; i < k / 2; ++i) {
            q += term;
            term *= y / (i + 1);
        }
        return std::exp(-y) * q;
    }
    term = std::sqrt(y) / (0.5 * std::sqrt(M_PI));  // y^(i−1/2) / Γ(i + 1/2) at i = 1
    for (int i = 1; i <= (k - 1) / 2; ++i) {
        q += term;
        term *= y / (i + 0.5);
    }
    return std::erfc(std::sqrt(y)) + std::exp(-y) * q;
}
}  // namespace

PatchExtinctions fitPatchesUnderLight(const std::vector<PatchPoints>& patches, double gamma,
                                      const ColourMixCurve& light)
{
    PatchExtinctions r;
    double sw = 0, swb = 0;
    for (const auto& pp : patches) try {
            ColourMixFit f = fitColourMix({pp}, gamma, false, &light);
            if (!f.converged || f.std_error.empty() || !(f.std_error[0] > 0)) continue;
            sw += 1 / (f.std_error[0] * f.std_error[0]);
            swb += f.curve.b / (f.std_error[0] * f.std_error[0]);
            r.fits[pp.name] = std::move(f);
        } catch (const Error&) {
            // Too few points for a patch alone.
        }
    if (r.fits.size() < 2) return r;
    r.b_mean = swb / sw;
    for (const auto& [name, f] : r.fits) r.chi2 += std::pow((f.curve.b - r.b_mean) / f.std_error[0], 2);
    r.dof = int(r.fits.size()) - 1;
    r.p_value = chi2Survival(r.chi2, r.dof);
    return r;
}

}  // namespace smokescan
