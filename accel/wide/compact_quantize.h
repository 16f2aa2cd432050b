#pragma once
/// The quantized child boxes of the compact layout (compact_layout.h): per node an origin and a
/// power-of-two scale per axis, per child box its planes as 8-bit steps of that scale from the
/// origin (as in "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs",
/// Ylitie, Karras and Laine, HPG 2017).
///
/// A plane is decoded as origin + float(q) * scale, by compact_decode below, in the walk and in
/// the quantizer alike (one function over T = float or a lane type). The planes are chosen with
/// that very decode, so a decoded box always contains the true one: lo is the largest step whose
/// decoded value is <= the true lo, hi the smallest whose decoded value is >= the true hi. With
/// the scale an exact power of two in [2^-126, 2^127] and q <= 255, float(q) * scale is exact (or
/// +inf, which only widens a hi plane). A fused multiply-add would NOT always give the same value:
/// where float(q) * scale overflows (scales near 2^121: frames spanning most of the float range)
/// the plain decode is +inf, while origin + q * scale rounded once can be finite and below the hi
/// plane it was chosen for (origin -FLT_MAX, scale 2^121, q 128: 2.0e31 fused, +inf plain, the
/// step a hi of 1e38 gets). Hence the plain form.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "accel/core/ray.h"
#include "simd/simd.h"

namespace arbor::accel {

/// A decoded plane: origin + float(q) * scale (T = float, or a lane type with q converted to float).
template <class T>
ARBOR_INLINE T compact_decode(const T& q, const T& scale, const T& origin) {
    return origin + q * scale;
}

/// The quantization frame of one axis of a node: the children's lowest lo is the origin, the
/// scale the smallest power of two (at least 2^-126, at most 2^127) whose 255 steps reach the
/// highest hi after decoding. `lo` <= `hi` finite (an empty node: any frame).
struct CompactAxis {
    float origin = 0.0f, scale = 1.0f;

    static CompactAxis fit(float lo, float hi) {
        CompactAxis a;
        if (!(lo <= hi) || !std::isfinite(lo) || !std::isfinite(hi)) return a;
        a.origin = lo;
        const double extent = double(hi) - double(lo);
        int e = -126;
        if (extent > 0.0) e = std::clamp(int(std::ceil(std::log2(extent / 255.0))), -126, 127);
        // (log2 of a double may round: step to the first exponent that reaches hi, decoded.)
        while (e > -126 && compact_decode(255.0f, std::ldexp(1.0f, e - 1), lo) >= hi) --e;
        while (e < 127 && compact_decode(255.0f, std::ldexp(1.0f, e), lo) < hi) ++e;
        a.scale = std::ldexp(1.0f, e);
        return a;
    }
    float decode(std::uint8_t q) const { return compact_decode(float(q), scale, origin); }
    /// The largest step whose decoded plane is <= lo (0 decodes to the origin, <= every lo).
    std::uint8_t quantize_lo(float lo) const {
        double q = std::floor((double(lo) - origin) / scale);
        q = std::clamp(q, 0.0, 255.0);
        auto s = std::uint8_t(q);
        while (s > 0 && decode(s) > lo) --s;
        while (s < 255 && decode(std::uint8_t(s + 1)) <= lo) ++s;
        return s;
    }
    /// The smallest step whose decoded plane is >= hi (255 reaches every hi, by fit).
    std::uint8_t quantize_hi(float hi) const {
        double q = std::ceil((double(hi) - origin) / scale);
        q = std::clamp(q, 0.0, 255.0);
        auto s = std::uint8_t(q);
        while (s < 255 && decode(s) < hi) ++s;
        while (s > 0 && decode(std::uint8_t(s - 1)) >= hi) --s;
        return s;
    }
};

}  // namespace arbor::accel
