// The lidar equation per beam: sub-rays over the footprint, smoke along the beam, mirror paths.
#include <algorithm>
#include <cmath>

#include "smokescan/sensors/physical_model.hpp"

namespace smokescan {
namespace {

/// Sub-ray directions: the centre and four rays at 0.7 of the half divergence (in the scan
/// plane and across it), an equal-weight quadrature of a Gaussian-ish footprint.
void footprint(const Vec3& d, double half_angle_rad, int n, std::vector<Vec3>& out)
{
    out.assign(1, d);
    if (n <= 1) return;
    const Vec3 helper = std::abs(d.z()) < 0.9 ? Vec3::UnitZ() : Vec3::UnitX();
    const Vec3 u = d.cross(helper).normalized(), v = d.cross(u);
    // The ring's offset and its cosines and sines, once for each thread, ring size and divergence.
    thread_local int ring_n = 0;
    thread_local double ring_half = -1, t = 0;
    thread_local std::vector<std::pair<double, double>> ring;
    if (ring_half != half_angle_rad) {
        t = std::tan(0.7 * half_angle_rad);
        ring_half = half_angle_rad;
    }
    if (ring_n != n) {
        ring.clear();
        for (int k = 0; k < n - 1; ++k) {
            const double a = 2 * M_PI * k / (n - 1);
            ring.emplace_back(std::cos(a), std::sin(a));
        }
        ring_n = n;
    }
    out.reserve(size_t(n));
    for (const auto& [c, s] : ring) out.push_back((d + t * (c * u + s * v)).normalized());
}

}  // namespace

BeamSignal traceBeamSignal(const Ray& ray, const LrfSpec& spec, const PhysicalParams& p, const Scene& scene,
                           const SurfaceSet& surfaces, const SmokeField& field, SurfaceHit* central_hit,
                           BeamSmoke* central_smoke)
{
    return traceBeamSignal(ray, spec.wavelength_nm, spec.range_max_m, p, scene, surfaces, field, central_hit,
                           central_smoke);
}

BeamSignal traceBeamSignal(const Ray& ray, double wavelength_nm, double range_max_m, const PhysicalParams& p,
                           const Scene& scene, const SurfaceSet& surfaces, const SmokeField& field,
                           SurfaceHit* central_hit, BeamSmoke* central_smoke,
                           const std::vector<double>* reflectance_factor)
{
    BeamSignal sig;
    traceBeamSignalInto(sig, ray, wavelength_nm, range_max_m, p, scene, surfaces, field, central_hit, central_smoke,
                        reflectance_factor);
    return sig;
}

void traceBeamSignalInto(BeamSignal& sig, const Ray& ray, double wavelength_nm, double range_max_m,
                         const PhysicalParams& p, const Scene& scene, const SurfaceSet& surfaces,
                         const SmokeField& field, SurfaceHit* central_hit, BeamSmoke* central_smoke,
                         const std::vector<double>* reflectance_factor)
{
    sig.clear();
    auto factor = [&](int surface) {
        return reflectance_factor && surface >= 0 && size_t(surface) < reflectance_factor->size()
            ? (*reflectance_factor)[size_t(surface)]
            : 1.0;
    };
    const double wl = wavelength_nm;
    const double half = 0.5e-3 * p.divergence_mrad;
    // Each beam's scratch, kept for each thread (a frame traces many beams).
    thread_local std::vector<Vec3> dirs;
    thread_local std::vector<SurfaceHit> hits;
    thread_local std::vector<double> blocked;
    footprint(ray.d, half, p.sub_rays, dirs);
    const double w = 1.0 / double(dirs.size());
    // Echoes beyond the sensor's range window still pull the phase or widen the waveform; look
    // a pulse length further than the maximum range.
    const double reach = range_max_m + 1.0;

    hits.resize(dirs.size());
    blocked.resize(dirs.size());
    double t_end = 0;
    // The central ray alone, the others (the footprint's ring) four at a time in packets.
    hits[0] = surfaces.closest(ray, reach);
    for (size_t j = 1; j < dirs.size(); j += 4) {
        Ray packet[4];
        const int m = int(std::min<size_t>(4, dirs.size() - j));
        for (int k = 0; k < m; ++k) packet[k] = Ray{ray.o, dirs[j + size_t(k)]};
        surfaces.closest4(packet, m, reach, &hits[j]);
    }
    for (size_t j = 0; j < dirs.size(); ++j) {
        blocked[j] = hits[j].endOr(reach);
        t_end = std::max(t_end, blocked[j]);
        if (hits[j].hit && hits[j].t_m <= range_max_m) sig.surface_in_range = true;
        if (hits[j].hit != hits[0].hit || (hits[j].hit && hits[j].surface != hits[0].surface))
            sig.mixed_surfaces = true;
    }
    if (central_hit) *central_hit = hits[0];

    // Smoke along the central ray: smoke varies little across a footprint of centimetres.
    BeamQuery q;
    q.wavelength_nm = wl;
    q.want_profile = true;
    thread_local BeamSmoke smoke, ms;  // the central ray's smoke, a mirror path's
    field.trace(ray, 0.0, t_end, q, smoke);
    thread_local std::vector<double> tau_sums, mirror_sums;  // the profiles' sums' storage
    const TauProfile tau(smoke.sigma_t_profile, tau_sums);
    std::sort(blocked.begin(), blocked.end());
    if (p.smoke_cell_m > 0)
        depositSmokeCells(p, tau, smoke.beta_profile, t_end, blocked, sig);
    else
        appendSmokeEchoes(p, tau, smoke.beta_profile, 0.0, t_end, 0.0, 1.0, 0.0, blocked, EchoSource::Smoke, sig);

    for (size_t j = 0; j < dirs.size(); ++j) {
        const SurfaceHit& h = hits[j];
        if (!h.hit) continue;
        const Material& m = scene.materials[size_t(h.material)];
        const double cos_t = std::abs(dirs[j].dot(h.normal));
        const double tau_R = tau.tau(h.t_m);
        const double k = factor(h.surface);
        const double P = k * w * surfaceEchoPower(p, m, wl, cos_t, h.t_m, tau_R);
        if (P > 0) {
            sig.echoes.push_back({h.t_m, P, EchoSource::Surface});
            sig.surface_power += P;
        }
        if (m.specular <= 0) continue;
        // Mirror path: the specular part of the beam goes on along the reflected direction and
        // whatever it meets returns the same way (reciprocity), seen at R + u.
        const double refl = k * m.specular * nirReflectance(m, wl);
        const double gain = w * refl * refl * std::exp(-2 * tau_R);
        if (gain < 1e-9) continue;
        const double alpha = std::max(1e-3, m.roughness * m.roughness);
        const double lobe_ratio = std::pow(2 * alpha / std::max(half, 1e-6), 2);
        const Vec3 d = dirs[j], n = h.normal;
        const Vec3 rd = (d - 2 * d.dot(n) * n).normalized();
        const Ray mray{ray.o + h.t_m * d + 1e-6 * n, rd};
        const double u_max = reach - h.t_m;
        if (u_max <= 0) continue;
        const SurfaceHit mh = surfaces.closest(mray, u_max);
        const double u_end = mh.endOr(u_max);
        field.trace(mray, 0.0, u_end, q, ms);
        const TauProfile mtau(ms.sigma_t_profile, mirror_sums);
        appendSmokeEchoes(p, mtau, ms.beta_profile, 0.0, u_end, h.t_m, gain, lobe_ratio, {}, EchoSource::Mirror, sig);
        if (mh.hit) {
            const Material& mm = scene.materials[size_t(mh.material)];
            const double u = mh.t_m, R = h.t_m + u;
            const double cos_m = std::abs(rd.dot(mh.normal));
            const double Pm = factor(mh.surface) * gain * M_PI * monostaticBrdf(mm, wl, cos_m) * cos_m * p.overlap(R) /
                (R * R + u * u * lobe_ratio) * std::exp(-2 * mtau.tau(u));
            if (Pm > 0) {
                sig.echoes.push_back({R, Pm, EchoSource::Mirror});
                sig.mirror_power += Pm;
            }
        }
    }
    std::sort(sig.echoes.begin(), sig.echoes.end(), [](const Echo& a, const Echo& b) { return a.range_m < b.range_m; });
    if (central_smoke) {
        // The paper model's bookkeeping up to the central surface, for reports and --tau.
        const double t_c = hits[0].endOr(range_max_m);
        BeamQuery qc;
        qc.wavelength_nm = wl;
        *central_smoke = t_c == t_end ? smoke : field.trace(ray, 0.0, t_c, qc);
    }
}

}  // namespace smokescan
