#pragma once
/// SplitMix64 (G. L. Steele, D. Lea, C. H. Flood, "Fast Splittable Pseudorandom Number
/// Generators", OOPSLA 2014), written once for every layer that needs deterministic numbers: the
/// auto selection's ray sample, the ray generator, the renderer's sample streams, procedural
/// jitter, the scene fingerprint and the benchmark scenes. Counter-based use (hash an index) makes
/// every number a pure function of its inputs, so results never depend on threads or order.
#include <cstdint>

namespace arbor::accel {

/// The generator's increment, the golden ratio in 64-bit fixed point.
inline constexpr std::uint64_t splitmix64_gamma = 0x9E3779B97F4A7C15ull;

/// The finaliser alone (Stafford's "Mix13" variant): a bijection of 64-bit words whose output bits
/// each depend on every input bit.
constexpr std::uint64_t splitmix64_mix(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/// SplitMix64 of `x`: the number the generator returns after state x (x + gamma, finalised). Used
/// as a 64-bit hash of a counter.
constexpr std::uint64_t splitmix64(std::uint64_t x) { return splitmix64_mix(x + splitmix64_gamma); }

/// Uniform in [0, 1) from the top 24 bits of `h` (1.0 is never returned).
constexpr float unit_float24(std::uint64_t h) { return float(h >> 40) * 0x1p-24f; }

/// The sequential generator: next() gives splitmix64(seed), splitmix64(seed + gamma), ...
struct SplitMix64 {
    std::uint64_t state = 0;
    constexpr std::uint64_t next() {
        const std::uint64_t x = state;
        state += splitmix64_gamma;
        return splitmix64(x);
    }
    /// Uniform in [0, 1) (unit_float24).
    constexpr float u01() { return unit_float24(next()); }
};

}  // namespace arbor::accel
