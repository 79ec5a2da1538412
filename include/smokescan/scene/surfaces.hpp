#pragma once
/// @file surfaces.hpp
/// @brief The scene's surfaces in Embree: closest-hit queries for beams and camera rays.
#include <memory>

#include "smokescan/scene/scene.hpp"

namespace smokescan {

struct SurfaceHit {
    bool hit = false;
    double t_m = kInf;  ///< distance along the ray [m]
    Vec3 normal = Vec3::UnitZ();  ///< unit geometric normal, facing the ray's origin
    int surface = -1;  ///< index into Scene::surfaces (the object id)
    int material = -1;  ///< index into Scene::materials

    /// Where the ray stops: at the hit, else at `limit_m` (the length it was traced for).
    double endOr(double limit_m) const { return hit ? t_m : limit_m; }
};

class SurfaceSet {
public:
    /// @brief Tessellates every surface of the scene into one Embree scene (geometry id =
    /// surface index). @throw Error for a mesh that cannot be read.
    explicit SurfaceSet(const Scene& scene);
    ~SurfaceSet();
    SurfaceSet(const SurfaceSet&) = delete;
    SurfaceSet& operator=(const SurfaceSet&) = delete;

    /// @brief Closest hit with t in (t_min_m, t_max_m]. Thread-safe.
    SurfaceHit closest(const Ray& ray, double t_max_m, double t_min_m = 0.0) const;

    /// @brief The closest hits of up to four rays (a beam's footprint), traced as one Embree
    /// packet, each with t in (0, t_max_m]: the same hits as closest() ray by ray, faster for rays
    /// that stay together. @param rays n rays, 1 ≤ n ≤ 4, any origins. @param out their hits, in
    /// the rays' order. @throw Error for another n. Thread-safe.
    void closest4(const Ray* rays, int n, double t_max_m, SurfaceHit* out) const;

private:
    /// The hit Embree reported (geometry id, t, unnormalised geometric normal) for a ray of direction d.
    SurfaceHit hitOf(unsigned geom_id, float t_far, Vec3 normal, const Vec3& d) const;
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace smokescan
