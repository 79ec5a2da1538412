#pragma once
/// @file timeline.hpp
/// @brief How a smoke volume's density scale changes with time [s]. The grid's values are
/// multiplied by the scale at each scan time.
///
/// | kind      | parameters                                   | scale(t)                              |
/// |-----------|----------------------------------------------|---------------------------------------|
/// | constant  | value (1)                                    | value                                 |
/// | keyframes | keys [(t_s, value)], interp, decay_s (0)     | linear / step / exp between keys; hold before the first; after the last hold, or decay e^{−Δt/decay_s} |
/// | machine   | on [(t0_s, t1_s)], fill_per_s, dissolve_s    | dρ/dt = fill_per_s·on(t) − ρ/dissolve_s, ρ(−∞) = 0 (exact solution) |
///
/// `machine` is a well-mixed room: a smoke machine filling it while on, the smoke leaking or
/// settling out with time constant dissolve_s.
#include <utility>
#include <vector>

namespace smokescan {

class DensityTimeline {
public:
    enum class Interp { Linear, Step, Exp };

    static DensityTimeline constant(double value = 1.0);
    /// @throw Error if times are not strictly increasing, values negative, or exp meets a zero.
    static DensityTimeline keyframes(std::vector<std::pair<double, double>> keys, Interp interp, double decay_s = 0.0);
    /// @throw Error on overlapping or reversed intervals, or non-positive rates.
    static DensityTimeline machine(std::vector<std::pair<double, double>> on_s, double fill_per_s, double dissolve_s);

    /// Density scale at time t [s].
    double at(double t_s) const;
    /// @brief The same time line with every value times k (k ≥ 0): the same smoke, k times as dense.
    /// @throw Error for k negative or not finite.
    DensityTimeline scaled(double k) const;

private:
    double base(double t_s) const;  ///< before scale_
    double scale_ = 1.0;
    enum class Kind { Constant, Keyframes, Machine } kind_ = Kind::Constant;
    double value_ = 1.0;
    std::vector<std::pair<double, double>> pts_;
    Interp interp_ = Interp::Linear;
    double decay_s_ = 0.0, fill_ = 0.0, dissolve_s_ = 1.0;
};

}  // namespace smokescan
