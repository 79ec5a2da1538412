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
    /// Two independent standard normals (both of Box–Muller's pair: half normal()'s cost each).
    void normalPair(double& a, double& b)
    {
        const double u1 = 1.0 - uniform(), u2 = uniform();
        const double r = std::sqrt(-2.0 * std::log(u1));
        a = r * std::cos(2.0 * M_PI * u2);
        b = r * std::sin(2.0 * M_PI * u2);
    }
    /// Standard normal (Box–Muller).
    double normal()
    {
        const double u1 = 1.0 - uniform(), u2 = uniform();
        return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
    }

private:
    uint64_t state_;
};

}  // namespace smokescan
