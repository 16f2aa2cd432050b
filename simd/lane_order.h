#pragma once
/// Ordering helpers for wide-node traversal: which children were hit, nearest first.
#include "simd/simd.h"

#include <bit>
#include <cstdint>

namespace arbor::simd {

/// Writes the lanes set in `bits` to `out` ordered by d[lane], nearest first (equal d: lower lane
/// first, i.e. a stable sort) and returns how many. The d of a lane in `bits` must not be NaN (an
/// entry distance of a hit never is). Typical wide nodes hit 1-3 children, so the counts 1 and 2
/// take a shortcut and the rest is an insertion sort, which beats a full sorting network there.
inline int order_hits(std::uint32_t bits, const float* d, std::uint8_t* out) {
    const int count = std::popcount(bits);
    if (count == 0) return 0;
    const int first = std::countr_zero(bits);
    out[0] = std::uint8_t(first);
    if (count == 1) return 1;
    bits &= bits - 1;
    if (count == 2) {
        const int second = std::countr_zero(bits);
        const bool swap = d[second] < d[first];
        out[swap ? 0 : 1] = std::uint8_t(second);
        out[swap ? 1 : 0] = std::uint8_t(first);
        return 2;
    }
    int n = 1;
    while (bits) {
        const int i = std::countr_zero(bits);
        bits &= bits - 1;
        int j = n++;
        for (; j > 0 && d[i] < d[out[j - 1]]; --j) out[j] = out[j - 1];
        out[j] = std::uint8_t(i);
    }
    return count;
}

/// The same with the distances in the lanes of t.
template <class T> inline int order_hits(std::uint32_t bits, const T& t, std::uint8_t* out) {
    alignas(64) float d[lanes<T>];
    store_lanes(t, d);
    return order_hits(bits, static_cast<const float*>(d), out);
}

}  // namespace arbor::simd
