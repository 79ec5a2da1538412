#pragma once
/// @file random.hpp
/// @brief Counter-based random numbers: a value is a pure function of (seed, keys), so results do
/// not depend on thread count or evaluation order.
#include <cmath>
#include <cstdint>

namespace smokescan {

inline uint64_t splitmix64(uint64_t x)
{
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

/// A small stream seeded from a key tuple.
class KeyedRng {
public:
    KeyedRng(uint64_t seed, uint64_t a, uint64_t b = 0, uint64_t c = 0)
        : state_(splitmix64(splitmix64(splitmix64(seed ^ 0x5DEECE66Dull) ^ a) ^ b) ^ c)
    {
    }
    uint64_t next() { return splitmix64(state_++); }
    /// Uniform in [0, 1).
    double uniform() { return double(next() >> 11) * 0x1.0p-53; }
    /// Standard normal (Box–Muller).
    double normal()
    {
        const double u1 = 1.0 - uniform(), u2 = uniform();
        return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
    }

    /// Standard normal by the ziggurat (see zigguratNormal): exact, about five times as fast.
    double normalZiggurat();

private:
    uint64_t state_;
};

/// @brief A standard normal drawn by Marsaglia and Tsang's ziggurat (J. Stat. Softw. 5(8), 2000)
/// in Doornik's form (2005): 128 layers of equal area under exp(−x²/2), a layer and a uniform
/// from one 64-bit draw; 99 % of draws are a multiply and a compare, the rest take the wedge's
/// exact test or the tail beyond R = 3.4426 by Marsaglia's exponential rejection. Exact: the
/// result has the normal distribution, not an approximation of it.
double zigguratNormal(KeyedRng& rng);

inline double KeyedRng::normalZiggurat() { return zigguratNormal(*this); }

}  // namespace smokescan
