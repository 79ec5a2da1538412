#pragma once
// Internal: the BeamModel implementations, made by makeBeamModel (beam_model.cpp). The paper and
// the physical models each share their plumbing (tracing, the three forms, the log's parameter);
// each sensor supplies only its own rule or receiver, in its folder.
#include "smokescan/sensors/beam_model.hpp"
#include "smokescan/sensors/physical_model.hpp"

namespace smokescan {

/// The random draws of one paper-model beam: the datasheet noise, and the extensions' draws
/// (sensors/extensions.hpp). The defaults are the medians: the noise-free, expected reading.
struct PaperDraws {
    double noise = 0;  ///< standard normal: the range noise
    double u_dropout = 0.5;  ///< uniform: a dropout sector's failure
    double z_threshold = 0;  ///< standard normal: where in the onset's spread this beam stops
    double u_return = 0.5;  ///< uniform: a smoke-stopped beam's short return
    double u_short = 0.5;  ///< uniform: where in (0, L) the short return lands
};

/// The paper model: the first surface within range and the smoke up to it, then the sensor's rule.
class PaperBeamModel : public BeamModel {
public:
    BeamResult read(const BeamWorld& w, const LaserBeam& beam, KeyedRng& rng, bool details) const final;
    BeamResult expected(const BeamWorld& w, const LaserBeam& beam) const final;
    double errorProbability(const BeamWorld& w, const LaserBeam& beam) const final;
    std::string smokeParameter() const final;

protected:
    using BeamModel::BeamModel;
    /// The sensor's rule for a beam that met `smoke` before `hit`.
    virtual BeamResult rule(const BeamWorld& w, const LaserBeam& beam, const SurfaceHit& hit, const BeamSmoke& smoke,
                            const PaperDraws& draws) const = 0;
    /// The probability that the rule reports an error value (for the expected reading `r`).
    virtual double ruleErrorProbability(const BeamWorld& w, const LaserBeam& beam, const BeamResult& r) const;
};

/// Paper model, URG-04LX (urg04lx/paper_urg.cpp): paperUrgBeam.
/// With extensions (sensors/extensions.hpp) it simulates what a diagnosis learned.
class PaperUrgModel final : public PaperBeamModel {
public:
    explicit PaperUrgModel(const SensorConfig& c) : PaperBeamModel(c) {}

private:
    BeamResult rule(const BeamWorld& w, const LaserBeam& beam, const SurfaceHit& hit, const BeamSmoke& smoke,
                    const PaperDraws& draws) const override;
    double ruleErrorProbability(const BeamWorld& w, const LaserBeam& beam, const BeamResult& r) const override;
};

/// Paper model, LMS200 (lms200/paper_sick.cpp): paperSickBeam.
class PaperSickModel final : public PaperBeamModel {
public:
    explicit PaperSickModel(const SensorConfig& c) : PaperBeamModel(c) {}

private:
    BeamResult rule(const BeamWorld& w, const LaserBeam& beam, const SurfaceHit& hit, const BeamSmoke& smoke,
                    const PaperDraws& draws) const override;
};

/// The physical model: the lidar equation over the beam's footprint, then the sensor's receiver.
class PhysicalBeamModel : public BeamModel {
public:
    BeamResult read(const BeamWorld& w, const LaserBeam& beam, KeyedRng& rng, bool details) const final;
    BeamResult expected(const BeamWorld& w, const LaserBeam& beam) const final;
    double errorProbability(const BeamWorld& w, const LaserBeam& beam) const final;
    double rangeSigma(const BeamWorld& w, const LaserBeam& beam) const final;
    BeamPrediction predict(const BeamWorld& w, const LaserBeam& beam) const final;
    std::string smokeParameter() const final;

protected:
    using BeamModel::BeamModel;
    /// A valid reading's standard deviation for a signal; NaN (the default): the datasheet's at
    /// the noise-free reading.
    virtual double receiveRangeSigma(const BeamSignal& s) const;
    /// The reading and error probability without extensions (beam_model.cpp).
    BeamResult readPlain(const BeamWorld& w, const Ray& ray, KeyedRng* rng) const;  ///< rng null: noise-free
    double errorProbabilityPlain(const BeamWorld& w, const Ray& ray) const;
    /// The same with the config's extensions (extension_rule.cpp): the URG's only; rng null: the
    /// noise-free reading (every draw at its median).
    BeamResult readExtended(const BeamWorld& w, const LaserBeam& beam, KeyedRng* rng) const;
    double errorProbabilityExtended(const BeamWorld& w, const LaserBeam& beam) const;
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
    double receiveRangeSigma(const BeamSignal& s) const override;
};

/// Physical model, LMS200 (lms200/pulsed_sick.cpp): first echo of the pulsed waveform.
class PulsedSickModel final : public PhysicalBeamModel {
public:
    explicit PulsedSickModel(const SensorConfig& c) : PhysicalBeamModel(c) {}

private:
    BeamResult receive(const BeamSignal& s, KeyedRng* rng) const override;
    double receiveErrorProbability(const BeamSignal& s) const override;
};

/// @brief The URG-04LX's models, by config.model (urg04lx/urg04lx_models.cpp).
std::unique_ptr<BeamModel> makeUrg04lxModel(const SensorConfig& config);
/// @brief The LMS200's models, by config.model (lms200/lms200_models.cpp).
std::unique_ptr<BeamModel> makeLms200Model(const SensorConfig& config);

}  // namespace smokescan
