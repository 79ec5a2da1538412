#pragma once
/// @file scanner.hpp
/// @brief Simulated laser scans of a scene over time.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "smokescan/scene/scene.hpp"
#include "smokescan/scene/surfaces.hpp"
#include "smokescan/sensor_config/beam_pattern.hpp"
#include "smokescan/sensors/beam_model.hpp"

namespace smokescan {

/// | field      | default | unit | meaning                                           |
/// |------------|---------|------|---------------------------------------------------|
/// | sensor     | ""      | –    | sensor name or type in the scene ("" = the first) |
/// | from_s     | scene   | s    | first scan time                                    |
/// | to_s       | scene   | s    | last scan time (inclusive when on the grid)        |
/// | rate_hz    | 1       | Hz   | scans per second                                   |
/// | seed       | 1       | –    | noise seed; results do not depend on thread count  |
/// | sensor_file| ""      | –    | sensor file applied to the mount (io/sensor_file.hpp) |
/// | model      | none    | –    | none = the sensor's own (after sensor_file); paper or physical |
/// | penetration_power | mount's | density·m | overrides the mount's when > 0         |
struct ScanConfig {
    std::string sensor;
    double from_s = kInf, to_s = kInf;
    double rate_hz = 1.0;
    uint64_t seed = 1;
    std::string sensor_file;
    std::optional<SensorModel> model;
    double penetration_power = 0;
    bool keep_beams = true;  ///< keep per-beam details (optical depth, hit) in Scan::beams
};

struct Scan {
    double time_s = 0;
    std::vector<double> angle_rad;
    std::vector<long long> value;  ///< reported values (range in the sensor's unit, or codes)
    std::vector<BeamResult> beams;  ///< details, if kept
};

class Scanner {
public:
    /// @throw Error for an unknown sensor or model, or a bad time range.
    Scanner(const Scene& scene, const SurfaceSet& surfaces, const ScanConfig& cfg);

    /// Scan times implied by the config: from_s + k/rate_hz up to to_s.
    std::vector<double> times() const;
    /// The scan at time t_s; `index` keys the noise stream.
    Scan scanAt(double t_s, uint64_t index) const;

    const LrfSpec& spec() const { return model_->spec(); }
    /// The mount with the sensor file, model and penetration power of the config applied.
    const SensorMount& mount() const { return mount_; }
    const BeamModel& model() const { return *model_; }
    /// World ray of beam i (at the run's first time, for a sensor that rides on a robot).
    Ray beamRay(int i) const;

private:
    const Scene& scene_;
    const SurfaceSet& surfaces_;
    ScanConfig cfg_;
    SensorMount mount_;
    std::shared_ptr<const BeamModel> model_;
    std::vector<PatternBeam> fan_;  ///< the laser's beams (sensor_config/beam_pattern.hpp)
};

}  // namespace smokescan
