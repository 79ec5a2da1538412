#pragma once
// Internal: rendering with an explicit medium (tests compare media the scene format cannot hold).
#include "render_medium.hpp"
#include "smokescan/render/renderer.hpp"

namespace smokescan {

RenderResult renderWithMedium(const Scene& scene, const SurfaceSet& surfaces, const CameraModel& camera,
                              const RenderMedium& medium, const RenderConfig& cfg);

}  // namespace smokescan
