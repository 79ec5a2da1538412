#include "smokescan/omni/omni_log.hpp"

#include <cmath>
#include <iomanip>

#include "smokescan/sensors/laser_log.hpp"

namespace smokescan {

void writeOmniLogHeader(std::ostream& o, const std::string& scene_source, const std::string& camera,
                        const std::string& trained, const OmniRangeConfig& range)
{
    o << "# smokescan omnirange " << scene_source << "\n# camera " << camera << ", trained on " << trained
      << ", threshold " << range.threshold << ", N " << range.filter.n_behind << ", K " << range.filter.k_free
      << ", range " << range.min_range_m << "-" << range.max_range_m
      << " m\n# format: time_s then pairs of (angle_rad, range_mm)\n";
}

void writeOmniLogScan(std::ostream& o, const OmniFrame& f)
{
    o << std::fixed << std::setprecision(3) << f.time_s;
    for (size_t i = 0; i < f.omni.range_m.size(); ++i)
        o << ' ' << std::setprecision(6) << f.omni.angle_rad[i] << ' ' << std::llround(f.omni.range_m[i] * 1000);
    o << '\n';
}

void writeOmniLaserLogHeader(std::ostream& o, const std::string& scene_source, const Scanner& laser)
{
    o << "# smokescan omnirange " << scene_source << ": the laser " << laser.mount().name << " at the omnicam's times\n"
      << "# format: time_s then pairs of (angle_rad, range_mm); error codes: " << laser.spec().errorValueSummary()
      << "\n";
}

void writeOmniLaserLogScan(std::ostream& o, const OmniFrame& f, const LrfSpec& spec)
{
    Scan s;
    s.time_s = f.time_s;
    s.angle_rad = f.laser_angle_rad;
    s.value = f.laser_value;
    writeLaserLogScan(o, s, spec);
}

}  // namespace smokescan
