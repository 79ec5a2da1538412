#include "smokescan/sensors/laser_log.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/io/image.hpp"
#include "smokescan/io/recorded.hpp"

namespace smokescan {

void writeLaserLogHeader(std::ostream& o, const std::vector<std::string>& header)
{
    for (const auto& h : header) o << "# " << h << '\n';
}

void writeLaserLogScan(std::ostream& o, const Scan& s, const LrfSpec& spec)
{
    const long long mm_per_unit = std::llround(spec.unit_m / 0.001);
    o << std::fixed << std::setprecision(3) << s.time_s;
    for (size_t i = 0; i < s.value.size(); ++i)
        o << ' ' << std::setprecision(6) << s.angle_rad[i] << ' ' << s.value[i] * mm_per_unit;
    o << '\n';
}

void writeLaserLog(const std::string& path, const std::vector<std::string>& header, const std::vector<Scan>& scans,
                   const LrfSpec& spec)
{
    AtomicFile f(path);
    writeLaserLogHeader(f.stream(), header);
    for (const Scan& s : scans) writeLaserLogScan(f.stream(), s, spec);
    f.commit();
}

std::vector<LaserLogScan> readLaserLog(const std::string& path) { return readRecordedLog(path).scans; }

void writeBeamCsvHeader(std::ostream& o)
{
    o << "time_s,beam,angle_rad,value,error,cause,surface,hit_m,column_regional,column_local,tau,power\n";
}

void writeBeamCsvScan(std::ostream& o, const Scan& s, const Scene& scene)
{
    o << std::setprecision(9);
    for (size_t i = 0; i < s.beams.size(); ++i) {
        const BeamResult& b = s.beams[i];
        o << shortest(s.time_s) << ',' << i << ',' << s.angle_rad[i] << ',' << s.value[i] << ',' << (b.error ? 1 : 0)
          << ',' << b.cause << ','
          << (b.hit.surface >= 0 ? scene.surfaces[size_t(b.hit.surface)].name : std::string("none")) << ','
          << (b.hit.hit ? b.hit.t_m : -1.0) << ',' << b.smoke.column_regional << ',' << b.smoke.column_local << ','
          << b.smoke.tau << ',' << b.power << '\n';
    }
}

void writeBeamCsv(const std::string& path, const std::vector<Scan>& scans, const Scene& scene)
{
    AtomicFile f(path);
    writeBeamCsvHeader(f.stream());
    for (const Scan& s : scans) writeBeamCsvScan(f.stream(), s, scene);
    f.commit();
}

void writeScanImage(const std::string& path, const std::vector<Scan>& scans, const LrfSpec& spec, double range_max_m,
                    int beam_px, int scan_px)
{
    if (scans.empty()) throw Error(path, "no scans to draw");
    const int nb = int(scans.front().value.size());
    Image img(nb * beam_px, int(scans.size()) * scan_px, 3);
    for (size_t k = 0; k < scans.size(); ++k)
        for (int i = 0; i < nb; ++i) {
            const long long v = scans[k].value[size_t(i)];
            float rgb[3];
            if (spec.isErrorValue(v)) {
                rgb[0] = 0.85f;
                rgb[1] = rgb[2] = 0.1f;
            } else {
                const float g = float(std::clamp(v * spec.unit_m / range_max_m, 0.0, 1.0));
                rgb[0] = rgb[1] = rgb[2] = g;
            }
            for (int y = 0; y < scan_px; ++y)
                for (int x = 0; x < beam_px; ++x)
                    for (int c = 0; c < 3; ++c) img.at(i * beam_px + x, int(k) * scan_px + y, c) = rgb[c];
        }
    writeImage(path, img);
}

}  // namespace smokescan
