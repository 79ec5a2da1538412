#include "smokescan/scene/surfaces.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <string>

#include "smokescan/core/error.hpp"
#include "smokescan/scene/mesh.hpp"

namespace smokescan {

struct SurfaceSet::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::vector<int> material_of;  // by geometry id
    ~Impl()
    {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

SurfaceSet::SurfaceSet(const Scene& s) : impl_(std::make_unique<Impl>())
{
    impl_->device = rtcNewDevice("verbose=0");
    if (!impl_->device) throw Error("embree", "cannot create a device");
    impl_->scene = rtcNewScene(impl_->device);
    rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
    for (size_t i = 0; i < s.surfaces.size(); ++i) {
        const TriMesh m = tessellate(s.surfaces[i]);
        RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), m.points_m.size()));
        for (size_t k = 0; k < m.points_m.size(); ++k)
            for (int a = 0; a < 3; ++a) v[3 * k + a] = float(m.points_m[k][a]);
        auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), m.triangles.size()));
        for (size_t k = 0; k < m.triangles.size(); ++k)
            for (int a = 0; a < 3; ++a) idx[3 * k + a] = unsigned(m.triangles[k][a]);
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(impl_->scene, g, unsigned(i));
        rtcReleaseGeometry(g);
        impl_->material_of.push_back(s.surfaces[i].material);
    }
    rtcCommitScene(impl_->scene);
}

SurfaceSet::~SurfaceSet() = default;

SurfaceHit SurfaceSet::closest(const Ray& ray, double t_max, double t_min) const
{
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    rh.ray.org_x = float(ray.o.x());
    rh.ray.org_y = float(ray.o.y());
    rh.ray.org_z = float(ray.o.z());
    rh.ray.dir_x = float(ray.d.x());
    rh.ray.dir_y = float(ray.d.y());
    rh.ray.dir_z = float(ray.d.z());
    rh.ray.tnear = float(t_min);
    rh.ray.tfar = std::isfinite(t_max) ? float(t_max) : std::numeric_limits<float>::infinity();
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.time = 0.0f;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl_->scene, &ctx, &rh);
    return hitOf(rh.hit.geomID, rh.ray.tfar, Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z), ray.d);
}

SurfaceHit SurfaceSet::hitOf(unsigned geom_id, float t_far, Vec3 normal, const Vec3& d) const
{
    SurfaceHit h;
    if (geom_id == RTC_INVALID_GEOMETRY_ID) return h;
    h.hit = true;
    h.t_m = t_far;
    h.surface = int(geom_id);
    h.material = impl_->material_of[geom_id];
    normal.normalize();
    h.normal = normal.dot(d) > 0 ? -normal : normal;
    return h;
}

void SurfaceSet::closest4(const Ray* rays, int n, double t_max_m, SurfaceHit* out) const
{
    if (n < 1 || n > 4) throw Error("embree", "a packet holds 1 to 4 rays, not " + std::to_string(n));
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    // Not RTC_INTERSECT_CONTEXT_FLAG_COHERENT: Debian's Embree 3.13.5 then misses surfaces the single
    // rays hit (the plume scene's hedges from the LMS200, 2026-11-27).
    alignas(16) int valid[4];
    alignas(16) RTCRayHit4 rh;
    const float t_far = std::isfinite(t_max_m) ? float(t_max_m) : std::numeric_limits<float>::infinity();
    for (int k = 0; k < 4; ++k) {
        const Ray& r = rays[std::min(k, n - 1)];  // unused lanes repeat the last ray, masked off
        valid[k] = k < n ? -1 : 0;
        rh.ray.org_x[k] = float(r.o.x());
        rh.ray.org_y[k] = float(r.o.y());
        rh.ray.org_z[k] = float(r.o.z());
        rh.ray.dir_x[k] = float(r.d.x());
        rh.ray.dir_y[k] = float(r.d.y());
        rh.ray.dir_z[k] = float(r.d.z());
        rh.ray.tnear[k] = 0.0f;
        rh.ray.tfar[k] = t_far;
        rh.ray.mask[k] = 0xFFFFFFFFu;
        rh.ray.time[k] = 0.0f;
        rh.ray.flags[k] = 0;
        rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect4(valid, impl_->scene, &ctx, &rh);
    for (int k = 0; k < n; ++k)
        out[k] =
            hitOf(rh.hit.geomID[k], rh.ray.tfar[k], Vec3(rh.hit.Ng_x[k], rh.hit.Ng_y[k], rh.hit.Ng_z[k]), rays[k].d);
}

}  // namespace smokescan
