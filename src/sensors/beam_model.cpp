#include "smokescan/sensors/beam_model.hpp"

#include <cstdio>

#include "beam_models.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/random.hpp"
#include "smokescan/scene/scene.hpp"
#include "smokescan/scene/surfaces.hpp"
#include "smokescan/sensor_config/laser_kind.hpp"

namespace smokescan {

BeamModel::BeamModel(const SensorConfig& c) : config_(c), spec_(specFor(c)) {}

std::unique_ptr<BeamModel> makeBeamModel(const SensorConfig& c)
{
    const LaserKind& kind = laserKind(c.type);
    if (c.extensions.changesBeams() && !kind.learnsExtensions())
        throw Error(c.sensor_file.empty() ? std::string("sensor") : c.sensor_file,
                    "[extensions] change the beams, but " + kind.withArticle() + "'s models take none");
    // Each kind's models and their factory are in its own folder (src/sensors/NAME/).
    using Factory = std::unique_ptr<BeamModel> (*)(const SensorConfig&);
    static const std::pair<SensorType, Factory> kFactories[] = {{SensorType::Urg04lx, makeUrg04lxModel},
                                                                {SensorType::Lms200, makeLms200Model}};
    for (const auto& [type, make] : kFactories)
        if (type == c.type) return make(c);
    throw Error("sensor", kind.withArticle() + " has no beam models");
}

double BeamModel::rangeSigma(const BeamWorld& w, const LaserBeam& beam) const
{
    const BeamResult r = expected(w, beam);
    return spec().rangeSigma(r.error ? r.hit.endOr(spec().range_max_m) : double(r.value) * spec().unit_m);
}

BeamPrediction BeamModel::predict(const BeamWorld& w, const LaserBeam& beam) const
{
    return {errorProbability(w, beam), expected(w, beam), rangeSigma(w, beam)};
}

bool regionalSmokeRising(const Scene& scene, double t_s)
{
    constexpr double kTrend_s = 3.0;
    auto mean = [&](double t0, double t1) {
        double sum = 0;
        for (int i = 0; i <= 20; ++i)
            for (const SmokeVolume& v : scene.volumes)
                if (v.role == SmokeRole::Regional) sum += v.timeline.at(t0 + (t1 - t0) * i / 20.0);
        return sum;
    };
    return mean(t_s, t_s + kTrend_s) > mean(t_s - kTrend_s, t_s);
}

namespace {

std::string namedValue(const char* name, double value)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s=%g", name, value);
    return buf;
}

}  // namespace

// ---- the paper model's plumbing ----

namespace {

struct PaperTrace {
    SurfaceHit hit;
    BeamSmoke smoke;
};

/// The first surface within range and the smoke up to it.
PaperTrace paperTrace(const BeamModel& m, const BeamWorld& w, const Ray& ray)
{
    PaperTrace t;
    t.hit = w.surfaces.closest(ray, m.spec().range_max_m);
    BeamQuery q;
    q.wavelength_nm = m.spec().wavelength_nm;
    q.local_threshold = m.config().paper.local_threshold;
    t.smoke = w.field.trace(ray, 0.0, t.hit.endOr(m.spec().range_max_m), q);
    return t;
}

}  // namespace

BeamResult PaperBeamModel::read(const BeamWorld& w, const LaserBeam& beam, KeyedRng& rng, bool) const
{
    const PaperTrace t = paperTrace(*this, w, beam.ray);
    PaperDraws d;
    d.noise = rng.normal();
    if (config().extensions.changesBeams()) {  // drawn after the noise: a plain model's stream is unchanged
        d.u_dropout = rng.uniform();
        d.z_threshold = rng.normal();
        d.u_return = rng.uniform();
        d.u_short = rng.uniform();
    }
    return rule(w, beam, t.hit, t.smoke, d);
}

BeamResult PaperBeamModel::expected(const BeamWorld& w, const LaserBeam& beam) const
{
    const PaperTrace t = paperTrace(*this, w, beam.ray);
    return rule(w, beam, t.hit, t.smoke, PaperDraws{});
}

double PaperBeamModel::errorProbability(const BeamWorld& w, const LaserBeam& beam) const
{
    return ruleErrorProbability(w, beam, expected(w, beam));
}

double PaperBeamModel::ruleErrorProbability(const BeamWorld&, const LaserBeam&, const BeamResult& r) const
{
    return r.error ? 1.0 : reportErrorProbability(spec(), r.true_range_m);
}

std::string PaperBeamModel::smokeParameter() const
{
    return namedValue("penetration_power", config().paper.penetration_power);
}

// ---- the physical model's plumbing ----

namespace {

struct PhysicalTrace {
    BeamSignal signal;
    SurfaceHit hit;
    BeamSmoke smoke;
};

/// The beam's echoes, and the central ray's hit and smoke (when `details`).
PhysicalTrace physicalTrace(const BeamModel& m, const BeamWorld& w, const Ray& ray, bool details)
{
    PhysicalTrace t;
    t.signal = traceBeamSignal(ray, m.spec(), m.config().physical, w.scene, w.surfaces, w.field, &t.hit,
                               details ? &t.smoke : nullptr);
    return t;
}

}  // namespace

BeamResult PhysicalBeamModel::read(const BeamWorld& w, const LaserBeam& beam, KeyedRng& rng, bool details) const
{
    if (config().extensions.changesBeams()) return readExtended(w, beam, &rng);
    PhysicalTrace t = physicalTrace(*this, w, beam.ray, details);
    BeamResult r = receive(t.signal, &rng);
    r.hit = t.hit;
    r.smoke = std::move(t.smoke);
    return r;
}

BeamResult PhysicalBeamModel::readPlain(const BeamWorld& w, const Ray& ray, KeyedRng* rng) const
{
    PhysicalTrace t = physicalTrace(*this, w, ray, true);
    BeamResult r = receive(t.signal, rng);
    r.hit = t.hit;
    r.smoke = std::move(t.smoke);
    return r;
}

BeamResult PhysicalBeamModel::expected(const BeamWorld& w, const LaserBeam& beam) const
{
    if (config().extensions.changesBeams()) return readExtended(w, beam, nullptr);
    PhysicalTrace t = physicalTrace(*this, w, beam.ray, true);
    BeamResult r = receive(t.signal, nullptr);
    r.hit = t.hit;
    r.smoke = std::move(t.smoke);
    return r;
}

double PhysicalBeamModel::errorProbability(const BeamWorld& w, const LaserBeam& beam) const
{
    if (config().extensions.changesBeams()) return errorProbabilityExtended(w, beam);
    return errorProbabilityPlain(w, beam.ray);
}

double PhysicalBeamModel::rangeSigma(const BeamWorld& w, const LaserBeam& beam) const
{
    const double s = receiveRangeSigma(physicalTrace(*this, w, beam.ray, false).signal);
    return std::isnan(s) ? BeamModel::rangeSigma(w, beam) : s;
}

double PhysicalBeamModel::receiveRangeSigma(const BeamSignal&) const { return NAN; }

BeamPrediction PhysicalBeamModel::predict(const BeamWorld& w, const LaserBeam& beam) const
{
    if (config().extensions.changesBeams()) return BeamModel::predict(w, beam);
    PhysicalTrace t = physicalTrace(*this, w, beam.ray, true);
    BeamPrediction p;
    p.p_error = receiveErrorProbability(t.signal);
    p.expected = receive(t.signal, nullptr);
    p.expected.hit = t.hit;
    p.expected.smoke = std::move(t.smoke);
    const double s = receiveRangeSigma(t.signal);
    p.range_sigma_m = std::isnan(s) ? BeamModel::rangeSigma(w, beam) : s;
    return p;
}

double PhysicalBeamModel::errorProbabilityPlain(const BeamWorld& w, const Ray& ray) const
{
    return receiveErrorProbability(physicalTrace(*this, w, ray, false).signal);
}

std::string PhysicalBeamModel::smokeParameter() const
{
    return namedValue("noise_floor", config().physical.noise_floor);
}

}  // namespace smokescan
