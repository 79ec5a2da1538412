#include "smokescan/media/medium.hpp"

#include <cmath>

#include "smokescan/core/error.hpp"

namespace smokescan {

double Medium::sigmaT(double wl) const
{
    const double x[3] = {550.0, 785.0, 905.0};
    const double y[3] = {sigma_t_550, sigma_t_785, sigma_t_905};
    int i = wl <= x[1] ? 0 : 1;  // segment [x[i], x[i+1]], extended at both ends
    if (y[i] <= 0 || y[i + 1] <= 0) {  // no power law through a zero: linear
        const double f = (wl - x[i]) / (x[i + 1] - x[i]);
        return std::max(0.0, y[i] + f * (y[i + 1] - y[i]));
    }
    const double a = std::log(y[i + 1] / y[i]) / std::log(x[i + 1] / x[i]);
    return y[i] * std::pow(wl / x[i], a);
}

double Medium::backscatterPerExtinction() const
{
    if (lidar_ratio_sr > 0) return 1.0 / lidar_ratio_sr;
    return albedo * (1 - g) / (4 * M_PI * (1 + g) * (1 + g));
}

Medium Medium::fromAngstrom(const std::string& name, double s550, double angstrom, double albedo, double g)
{
    Medium m;
    m.name = name;
    m.sigma_t_550 = s550;
    m.sigma_t_785 = s550 * std::pow(785.0 / 550.0, -angstrom);
    m.sigma_t_905 = s550 * std::pow(905.0 / 550.0, -angstrom);
    m.albedo = albedo;
    m.g = g;
    return m;
}

Medium Medium::preset(const std::string& name)
{
    if (name == "theatrical_fog") return fromAngstrom(name, kCalibratedSigmaT, 0.0, 0.97, 0.7);
    if (name == "soot") return fromAngstrom(name, kCalibratedSigmaT, 1.0, 0.3, 0.6);
    if (name == "fine_smoke") return fromAngstrom(name, kCalibratedSigmaT, 2.0, 0.9, 0.7);
    throw Error("", "unknown medium preset '" + name + "' (theatrical_fog, soot, fine_smoke)");
}

}  // namespace smokescan
