#include "smokescan/sensors/beam_result.hpp"

#include <algorithm>
#include <cmath>

namespace smokescan {

BeamResult& markError(BeamResult& r, long long code, const char* cause)
{
    r.error = true;
    r.value = code;
    r.cause = cause;
    return r;
}

BeamResult& reportRange(const LrfSpec& spec, double range, double noise, BeamResult& r)
{
    if (!std::isfinite(range) || range > spec.range_max_m || range < spec.range_min_m)
        return markError(r, spec.no_return_code, "out_of_range");
    r.true_range_m = range;
    const double measured = range + spec.rangeSigma(range) * noise;
    const long long v = std::llround(std::max(measured, spec.range_min_m) / spec.unit_m);
    if (spec.isErrorValue(v)) return markError(r, spec.no_return_code, "out_of_range");
    r.value = v;
    return r;
}

double reportErrorProbability(const LrfSpec& spec, double range)
{
    if (!std::isfinite(range) || range > spec.range_max_m || range < spec.range_min_m) return 1.0;
    // Error values outside first_range_value…last_range_value: the measured range rounds onto
    // them beyond (last + ½)·unit (readings below the window are raised to range_min_m, a value).
    const double edge = (double(spec.last_range_value) + 0.5) * spec.unit_m;
    return 0.5 * std::erfc((edge - range) / (spec.rangeSigma(range) * std::sqrt(2.0)));
}

}  // namespace smokescan
