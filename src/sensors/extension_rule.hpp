#pragma once
// Internal: what a sensor file's extensions (extensions.hpp) make of one beam, shared by the
// URG-04LX's paper model (urg04lx/paper_urg.cpp) and its physical model (extension_rule.cpp).
#include "smokescan/core/quadrature.hpp"
#include "smokescan/sensor_config/extensions.hpp"
#include "smokescan/sensors/beam_model.hpp"

namespace smokescan {

struct SurfaceHit;

/// One beam's extensions: its dropout, the ln of the factor its smoke threshold is moved by
/// (its surface's threshold factor and the hysteresis' half-shift, − while the smoke rises), and
/// its surface's range bias.
struct BeamExtension {
    double dropout = 0;
    double threshold_shift = 0;  ///< ln(P' / P)
    double range_bias = 0;  ///< β [1/(density·m)]
};

/// @brief The extensions that apply to a beam that hit `hit`.
BeamExtension extensionOf(const ModelExtensions& e, const BeamWorld& w, const LaserBeam& beam, const SurfaceHit& hit);

}  // namespace smokescan
