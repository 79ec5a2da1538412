#pragma once
// Internal: the four BeamModel implementations, made by makeBeamModel (beam_model.cpp).
#include "smokescan/sensors/beam_model.hpp"
#include "smokescan/sensors/physical_model.hpp"

namespace smokescan {

/// Paper model, URG-04LX: regional smoke column above the penetration power, or any local
/// smoke, gives error 0.
class PaperUrgModel final : public BeamModel {
public:
    explicit PaperUrgModel(const SensorConfig& c) : BeamModel(c) {}
    BeamResult read(const BeamWorld& w, const Ray& ray, KeyedRng& rng, bool details) const override;
    BeamResult expected(const BeamWorld& w, const Ray& ray) const override;
    double errorProbability(const BeamWorld& w, const Ray& ray) const override;
    std::string smokeParameter() const override;
};

/// Paper model, LMS200: local smoke is an obstacle; regional smoke is seen through.
class PaperSickModel final : public BeamModel {
public:
    explicit PaperSickModel(const SensorConfig& c) : BeamModel(c) {}
    BeamResult read(const BeamWorld& w, const Ray& ray, KeyedRng& rng, bool details) const override;
    BeamResult expected(const BeamWorld& w, const Ray& ray) const override;
    double errorProbability(const BeamWorld& w, const Ray& ray) const override;
    std::string smokeParameter() const override;
};

/// Physical model, URG-04LX: AMCW phase of the summed lidar-equation echoes.
class AmcwUrgModel final : public BeamModel {
public:
    explicit AmcwUrgModel(const SensorConfig& c) : BeamModel(c) {}
    BeamResult read(const BeamWorld& w, const Ray& ray, KeyedRng& rng, bool details) const override;
    BeamResult expected(const BeamWorld& w, const Ray& ray) const override;
    double errorProbability(const BeamWorld& w, const Ray& ray) const override;
    std::string smokeParameter() const override;
};

/// Physical model, LMS200: first echo of the pulsed waveform.
class PulsedSickModel final : public BeamModel {
public:
    explicit PulsedSickModel(const SensorConfig& c) : BeamModel(c) {}
    BeamResult read(const BeamWorld& w, const Ray& ray, KeyedRng& rng, bool details) const override;
    BeamResult expected(const BeamWorld& w, const Ray& ray) const override;
    double errorProbability(const BeamWorld& w, const Ray& ray) const override;
    std::string smokeParameter() const override;
};

/// The paper models' trace: the first surface within range and the smoke up to it.
struct PaperTrace {
    SurfaceHit hit;
    BeamSmoke smoke;
};
PaperTrace paperTrace(const BeamModel& m, const BeamWorld& w, const Ray& ray);

/// The physical models' trace: the beam's echoes, and the central ray's hit and smoke.
struct PhysicalTrace {
    BeamSignal signal;
    SurfaceHit hit;
    BeamSmoke smoke;
};
PhysicalTrace physicalTrace(const BeamModel& m, const BeamWorld& w, const Ray& ray, bool details);

/// `name=value` with %g, for smokeParameter().
std::string namedValue(const char* name, double value);

}  // namespace smokescan
