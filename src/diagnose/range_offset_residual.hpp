#pragma once
// Internal: the residual of a channel's range bias fit (lidar_causes.cpp, docs/diagnosis.md).
namespace smokescan::detail {

/// One clear beam's range residual (recorded − replayed) against an offset common to every
/// channel, x[0], plus the tested channel's own, x[1] (on that channel's beams only), in units of
/// the residuals' sd: r = (residual − x[0] − [channel]·x[1]) / sd.
struct RangeOffsetResidual {
    RangeOffsetResidual(double residual_m, double sd_m, bool on_channel)
        : residual_m(residual_m), sd_m(sd_m), on_channel(on_channel)
    {
    }
    template <typename T>
    bool operator()(const T* x, T* r) const
    {
        r[0] = (T(residual_m) - x[0] - (on_channel ? x[1] : T(0))) / T(sd_m);
        return true;
    }
    double residual_m, sd_m;
    bool on_channel;
};

}  // namespace smokescan::detail
