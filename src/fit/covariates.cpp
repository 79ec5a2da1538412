#include "smokescan/fit/covariates.hpp"

#include <tbb/parallel_for.h>

#include <cmath>
#include <iomanip>
#include <sstream>

#include "smokescan/core/format.hpp"
#include "smokescan/io/atomic_file.hpp"

namespace smokescan {

void writeCovariates(const std::string& path, const RecordedLog& log, const SensorFitResult& fit, const Scene& scene,
                     const SurfaceSet& surfaces, const SensorMount& mount, const LrfSpec& spec, bool all_beams)
{
    AtomicFile f(path);
    std::ostream& o = f.stream();
    o << "time_s,beam,angle_rad,group,measured_m,error,saturation,surface,material,incidence_deg,surface_range_m,"
         "column_density_m,tau\n";
    BeamQuery q;
    q.wavelength_nm = spec.wavelength_nm;
    for (size_t k = 0; k < log.scans.size(); ++k) {
        const LaserLogScan& s = log.scans[k];
        const SmokeField field = SmokeField::at(scene.volumes, s.time_s);
        const double S = k < fit.aligned.size() ? fit.aligned[k].saturation : NAN;
        std::vector<std::string> rows(s.range.size());
        tbb::parallel_for(size_t(0), s.range.size(), [&](size_t i) {
            const double a = s.angle_rad[i];
            std::string group;
            for (const auto& g : fit.groups)
                if (g.contains(a)) group = g.name;
            if (group.empty() && !all_beams) return;
            const Ray ray = mount.beamRay(a);
            const SurfaceHit h = surfaces.closest(ray, spec.range_max_m);
            const BeamSmoke sm = field.trace(ray, 0.0, h.endOr(spec.range_max_m), q);
            const double m = s.range[i] * log.unit_m;
            const bool err = spec.isErrorRange(m);
            std::ostringstream r;
            r << std::setprecision(9) << shortest(s.time_s) << ',' << i << ',' << a << ',' << group << ',';
            if (!err) r << m;
            r << ',' << int(err) << ',';
            if (!std::isnan(S)) r << S;
            if (h.hit) {
                const Surface& sf = scene.surfaces[size_t(h.surface)];
                r << ',' << sf.name << ',' << scene.materials[size_t(sf.material)].name << ','
                  << std::acos(std::clamp(std::abs(h.normal.dot(ray.d)), 0.0, 1.0)) * 180 / M_PI << ',' << h.t_m;
            } else {
                r << ",none,,,";
            }
            r << ',' << sm.column_regional + sm.column_local << ',' << sm.tau << '\n';
            rows[i] = r.str();
        });
        for (const auto& row : rows) o << row;
    }
    f.commit();
}

}  // namespace smokescan
