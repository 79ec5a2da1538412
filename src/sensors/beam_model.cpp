#include "smokescan/sensors/beam_model.hpp"

#include <cstdio>

#include "beam_models.hpp"
#include "smokescan/core/random.hpp"
#include "smokescan/scene/scene.hpp"
#include "smokescan/scene/surfaces.hpp"

namespace smokescan {

BeamModel::BeamModel(const SensorConfig& c) : config_(c), spec_(specFor(c)) {}

std::unique_ptr<BeamModel> makeBeamModel(const SensorConfig& c)
{
    switch (c.type) {
    case SensorType::Urg04lx:
        if (c.model == SensorModel::Physical) return std::make_unique<AmcwUrgModel>(c);
        return std::make_unique<PaperUrgModel>(c);
    case SensorType::Lms200:
        if (c.model == SensorModel::Physical) return std::make_unique<PulsedSickModel>(c);
        return std::make_unique<PaperSickModel>(c);
    }
    return nullptr;
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

BeamResult PaperBeamModel::read(const BeamWorld& w, const Ray& ray, KeyedRng& rng, bool) const
{
    const PaperTrace t = paperTrace(*this, w, ray);
    return rule(t.hit, t.smoke, rng.normal());
}

BeamResult PaperBeamModel::expected(const BeamWorld& w, const Ray& ray) const
{
    const PaperTrace t = paperTrace(*this, w, ray);
    return rule(t.hit, t.smoke, 0.0);
}

double PaperBeamModel::errorProbability(const BeamWorld& w, const Ray& ray) const
{
    const BeamResult r = expected(w, ray);
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

BeamResult PhysicalBeamModel::read(const BeamWorld& w, const Ray& ray, KeyedRng& rng, bool details) const
{
    PhysicalTrace t = physicalTrace(*this, w, ray, details);
    BeamResult r = receive(t.signal, &rng);
    r.hit = t.hit;
    r.smoke = std::move(t.smoke);
    return r;
}

BeamResult PhysicalBeamModel::expected(const BeamWorld& w, const Ray& ray) const
{
    PhysicalTrace t = physicalTrace(*this, w, ray, true);
    BeamResult r = receive(t.signal, nullptr);
    r.hit = t.hit;
    r.smoke = std::move(t.smoke);
    return r;
}

double PhysicalBeamModel::errorProbability(const BeamWorld& w, const Ray& ray) const
{
    return receiveErrorProbability(physicalTrace(*this, w, ray, false).signal);
}

std::string PhysicalBeamModel::smokeParameter() const
{
    return namedValue("noise_floor", config().physical.noise_floor);
}

}  // namespace smokescan
