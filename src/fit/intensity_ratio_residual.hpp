#pragma once
// One beam's recorded peak (its intensity brought to the replay's range) against the replay's at
// the surface's reflectance factor k, in the peak's noise sd (fit/lidar_fit.hpp):
// (y − I_exp·g(k)) / u, g the sample's scaleAt.
#include "smokescan/fit/lidar_fit.hpp"

namespace smokescan::detail {

struct IntensityRatioResidual {
    IntensityRatioResidual(double recorded, const LidarIntensitySample& x, double noise)
        : recorded_(recorded), x_(x), noise_(noise)
    {
    }
    template <class T>
    bool operator()(const T* k, T* r) const
    {
        r[0] = (T(recorded_) - T(double(x_.expected)) * x_.scaleAt(k[0])) / T(noise_);
        return true;
    }
    double recorded_;
    LidarIntensitySample x_;
    double noise_;
};

}  // namespace smokescan::detail
