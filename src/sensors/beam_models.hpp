#pragma once
// Internal: the BeamModel implementations, made by makeBeamModel (beam_model.cpp). The paper and
// the physical models each share their plumbing (tracing, the three forms, the log's parameter);
// each sensor supplies only its own rule or receiver, in its folder.
#include "smokescan/sensors/beam_model.hpp"
#include "smokescan/sensors/physical_model.hpp"

namespace smokescan {

/// The paper model: the first surface within range and the smoke up to it, then the sensor's rule.
class PaperBeamModel : public BeamModel {
public:
    BeamResult read(const BeamWorld& w, const Ray& ray, KeyedRng& rng, bool details) const final;
    BeamResult expected(const BeamWorld& w, const Ray& ray) const final;
    double errorProbability(const BeamWorld& w, const Ray& ray) const final;
    std::string smokeParameter() const final;

protected:
    using BeamModel::BeamModel;
    /// The sensor's rule for a beam that met `smoke` before `hit`; `noise` a standard normal draw.
    virtual BeamResult rule(const SurfaceHit& hit, const BeamSmoke& smoke, double noise) const = 0;
};

/// Paper model, URG-04LX (urg04lx/paper_urg.cpp): paperUrgBeam.
class PaperUrgModel final : public PaperBeamModel {
public:
    explicit PaperUrgModel(const SensorConfig& c) : PaperBeamModel(c) {}

private:
    BeamResult rule(const SurfaceHit& hit, const BeamSmoke& smoke, double noise) const override;
};

/// Paper model, LMS200 (lms200/paper_sick.cpp): paperSickBeam.
class PaperSickModel final : public PaperBeamModel {
public:
    explicit PaperSickModel(const SensorConfig& c) : PaperBeamModel(c) {}

private:
    BeamResult rule(const SurfaceHit& hit, const BeamSmoke& smoke, double noise) const override;
};

/// The physical model: the lidar equation over the beam's footprint, then the sensor's receiver.
class PhysicalBeamModel : public BeamModel {
public:
    BeamResult read(const BeamWorld& w, const Ray& ray, KeyedRng& rng, bool details) const final;
    BeamResult expected(const BeamWorld& w, const Ray& ray) const final;
    double errorProbability(const BeamWorld& w, const Ray& ray) const final;
    std::string smokeParameter() const final;

protected:
    using BeamModel::BeamModel;
    /// The receiver's reading of a signal; rng null: without noise.
    virtual BeamResult receive(const BeamSignal& s, KeyedRng* rng) const = 0;
    /// The probability that the receiver reports an error value for the signal.
    virtual double receiveErrorProbability(const BeamSignal& s) const = 0;
};

/// Physical model, URG-04LX (urg04lx/amcw_urg.cpp): AMCW phase of the summed echoes.
class AmcwUrgModel final : public PhysicalBeamModel {
public:
    explicit AmcwUrgModel(const SensorConfig& c) : PhysicalBeamModel(c) {}

private:
    BeamResult receive(const BeamSignal& s, KeyedRng* rng) const override;
    double receiveErrorProbability(const BeamSignal& s) const override;
};

/// Physical model, LMS200 (lms200/pulsed_sick.cpp): first echo of the pulsed waveform.
class PulsedSickModel final : public PhysicalBeamModel {
public:
    explicit PulsedSickModel(const SensorConfig& c) : PhysicalBeamModel(c) {}

private:
    BeamResult receive(const BeamSignal& s, KeyedRng* rng) const override;
    double receiveErrorProbability(const BeamSignal& s) const override;
};

}  // namespace smokescan
