#include "smokescan/omni/sensors_versus_smoke.hpp"

#include "smokescan/core/error.hpp"
#include "smokescan/media/smoke.hpp"

namespace smokescan {

SensorsVersusSmoke::SensorsVersusSmoke(const Scene& scene, const SurfaceSet& surfaces, const OmniRangeConfig& omni,
                                       const VersusSmokeConfig& cfg)
    : scene_(scene), surfaces_(surfaces), omni_(omni), cfg_(cfg)
{
    if (scene.sensors.empty()) throw Error(scene.source, "the scene has no laser to compare with");
    tallies_.emplace_back("omnicam", omni.max_range_m, cfg.tally);
    for (const SensorMount& m : scene.sensors) {
        ScanConfig sc;
        sc.sensor = m.name;
        sc.seed = cfg.seed;
        sc.from_s = sc.to_s = scene.t_start_s;
        sc.keep_beams = true;
        lasers_.push_back(std::make_unique<Scanner>(scene, surfaces, sc));
        tallies_.emplace_back(m.name, lasers_.back()->spec().range_max_m, cfg.tally);
    }
}

void SensorsVersusSmoke::add(const OmniFrame& f, double height_m, uint64_t k)
{
    const SmokeField smoke = SmokeField::at(scene_.volumes, f.time_s);
    const ScanlineTruth truth =
        scanlineTruth(surfaces_, smoke, f.camera_pose, height_m, f.omni.angle_rad, omni_.max_range_m, cfg_.truth);
    for (size_t i = 0; i < f.omni.range_m.size(); ++i)
        tallies_[0].add(truth.column[i], truth.range_m[i], f.omni.range_m[i]);
    for (size_t j = 0; j < lasers_.size(); ++j) {
        const Scanner& laser = *lasers_[j];
        const Scan s = laser.scanAt(f.time_s, k);
        const LrfSpec& spec = laser.spec();
        for (size_t i = 0; i < s.beams.size(); ++i) {
            const BeamResult& b = s.beams[i];
            tallies_[j + 1].add(b.smoke.column_regional + b.smoke.column_local, b.hit.endOr(kInf),
                                spec.rangeOf(s.value[i]));
        }
    }
}

}  // namespace smokescan
