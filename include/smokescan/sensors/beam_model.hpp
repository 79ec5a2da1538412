#pragma once
/// @file beam_model.hpp
/// @brief One interface for the sensor models: how a beam of a given sensor, under a given
/// model, turns the scene and its smoke into a reported value. Built once from a typed config by
/// makeBeamModel(); the Scanner, the fits and the diagnosis use it without knowing which it is.
///
/// | sensor   | model    | implementation                     | error values (sensor_kind.hpp)       |
/// |----------|----------|------------------------------------|--------------------------------------|
/// | urg04lx  | paper    | src/sensors/urg04lx/paper_urg.cpp  | 0 (smoke, nothing in range)          |
/// | urg04lx  | physical | src/sensors/urg04lx/amcw_urg.cpp   | 0, 1, 8, 18                          |
/// | lms200   | paper    | src/sensors/lms200/paper_sick.cpp  | 8183 (nothing in range)              |
/// | lms200   | physical | src/sensors/lms200/pulsed_sick.cpp | 8183, 8189, 8191                     |
///
/// Each model gives three forms of a beam: a reading with the sensor's noise (read), the reading
/// without noise (expected), and the probability of an error value (errorProbability), the
/// predictive form fits and the diagnosis compare recorded readings with.
#include <memory>
#include <string>

#include "smokescan/media/smoke.hpp"
#include "smokescan/sensor_config/sensor_config.hpp"
#include "smokescan/sensors/beam_result.hpp"

namespace smokescan {

struct Scene;
class SurfaceSet;
class KeyedRng;

/// What a beam meets at one instant: the scene's surfaces and materials, and its smoke.
struct BeamWorld {
    const Scene& scene;
    const SurfaceSet& surfaces;
    const SmokeField& field;
    bool smoke_rising = false;  ///< the regional smoke is thickening now (an extension's hysteresis)
};

/// One beam of a scan: its world ray and its angle in the sensor's convention.
struct LaserBeam {
    Ray ray;
    double angle_rad = 0;  ///< (an extension's dropout sector)
    LaserBeam(const Ray& r, double angle = 0) : ray(r), angle_rad(angle) {}  // NOLINT: a ray is a beam
};

/// A beam's predictive form in one: what predicts a recorded value's probability.
struct BeamPrediction {
    double p_error = 0;  ///< errorProbability
    BeamResult expected;  ///< the reading without noise
    double range_sigma_m = 0;  ///< rangeSigma
};

/// A sensor model: one implementation per sensor type and model.
class BeamModel {
public:
    virtual ~BeamModel() = default;

    const SensorConfig& config() const { return config_; }
    const LrfSpec& spec() const { return spec_; }

    /// @brief One beam's reading, the sensor's noise drawn from `rng`.
    /// @param details fill the result's smoke bookkeeping (columns, optical depth to the surface)
    virtual BeamResult read(const BeamWorld& world, const LaserBeam& beam, KeyedRng& rng, bool details) const = 0;
    /// @brief The reading without any noise.
    virtual BeamResult expected(const BeamWorld& world, const LaserBeam& beam) const = 0;
    /// @brief Probability that the beam reports an error value.
    virtual double errorProbability(const BeamWorld& world, const LaserBeam& beam) const = 0;
    /// @brief The standard deviation of a valid reading [m] (the datasheet's at its noise-free
    /// range, unless the model's receiver says otherwise).
    virtual double rangeSigma(const BeamWorld& world, const LaserBeam& beam) const;
    /// @brief The three at once (a model may trace the beam once for them).
    virtual BeamPrediction predict(const BeamWorld& world, const LaserBeam& beam) const;
    /// @brief The model's smoke parameter as `name=value`, for log headers.
    virtual std::string smokeParameter() const = 0;

protected:
    explicit BeamModel(const SensorConfig& config);

private:
    SensorConfig config_;
    LrfSpec spec_;
};

/// @brief The model a config names (its type and model), built once.
/// @throw Error naming the config's sensor file when it extends (sensors/extensions.hpp) another
/// model than the URG-04LX's paper model.
std::unique_ptr<BeamModel> makeBeamModel(const SensorConfig& config);

/// @brief Whether the scene's regional smoke is thickening at t_s: the sum of its regional volumes'
/// time-line scales, averaged over the next 3 s, exceeds its average over the last 3 s (the trend
/// the diagnosis reads from the camera's saturation, diagnose/replay.hpp).
bool regionalSmokeRising(const Scene& scene, double t_s);

}  // namespace smokescan
