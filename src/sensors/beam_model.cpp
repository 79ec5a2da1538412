#include "smokescan/sensors/beam_model.hpp"

#include <cstdio>

#include "beam_models.hpp"
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

PhysicalTrace physicalTrace(const BeamModel& m, const BeamWorld& w, const Ray& ray, bool details)
{
    PhysicalTrace t;
    t.signal = traceBeamSignal(ray, m.spec(), m.config().physical, w.scene, w.surfaces, w.field, &t.hit,
                               details ? &t.smoke : nullptr);
    return t;
}

std::string namedValue(const char* name, double value)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s=%g", name, value);
    return buf;
}

}  // namespace smokescan
