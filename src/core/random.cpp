#include "smokescan/core/random.hpp"

#include <array>
#include <cmath>

namespace smokescan {
namespace {

/// The ziggurat's layers for f(x) = exp(−x²/2): x[i] is the right edge of layer i (x[0] the base
/// layer's equivalent width V/f(R), x[1] = R, x[N] = 0), ratio[i] = x[i+1]/x[i] the share of
/// layer i that lies wholly under the curve.
struct Ziggurat {
    static constexpr int N = 128;
    static constexpr double R = 3.442619855899;  ///< where the tail starts
    static constexpr double V = 9.91256303526217e-3;  ///< each layer's area
    std::array<double, N + 1> x{};
    std::array<double, N> ratio{};

    Ziggurat()
    {
        double f = std::exp(-0.5 * R * R);
        x[0] = V / f;
        x[1] = R;
        for (int i = 2; i < N; ++i) {
            // Layer i − 1 spans heights f(x[i−1]) … f(x[i]) over width x[i−1]: area V.
            x[size_t(i)] = std::sqrt(-2 * std::log(V / x[size_t(i - 1)] + f));
            f = std::exp(-0.5 * x[size_t(i)] * x[size_t(i)]);
        }
        x[N] = 0;
        for (int i = 0; i < N; ++i) ratio[size_t(i)] = x[size_t(i + 1)] / x[size_t(i)];
    }
};

const Ziggurat& ziggurat()
{
    static const Ziggurat z;
    return z;
}

/// Uniform in (0, 1]: safe to take the log of.
double openUniform(KeyedRng& rng) { return (double(rng.next() >> 11) + 1) * 0x1.0p-53; }

/// Beyond R by Marsaglia's rejection from an exponential.
double tail(KeyedRng& rng, bool negative)
{
    constexpr double R = Ziggurat::R;
    double x, y;
    do {
        x = std::log(openUniform(rng)) / R;  // ≤ 0
        y = std::log(openUniform(rng));
    } while (-2 * y < x * x);
    return negative ? x - R : R - x;
}

}  // namespace

double zigguratNormal(KeyedRng& rng)
{
    const Ziggurat& z = ziggurat();
    for (;;) {
        const uint64_t bits = rng.next();
        const size_t i = size_t(bits & (Ziggurat::N - 1));  // the layer: the low 7 bits
        const double u = double(bits >> 11) * 0x1.0p-52 - 1;  // [−1, 1): the high 53 bits
        if (std::abs(u) < z.ratio[i]) return u * z.x[i];  // wholly under the curve
        if (i == 0) return tail(rng, u < 0);
        // The wedge between f(x[i]) and f(x[i+1]): accept under the curve.
        const double x = u * z.x[i];
        const double f0 = std::exp(-0.5 * (z.x[i] * z.x[i] - x * x));
        const double f1 = std::exp(-0.5 * (z.x[i + 1] * z.x[i + 1] - x * x));
        if (f1 + rng.uniform() * (f0 - f1) < 1.0) return x;
    }
}

}  // namespace smokescan
