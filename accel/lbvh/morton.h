#pragma once
/// Morton (Z-order) codes of points quantized to a box: 30 bits (10 per axis) or 63 bits (21 per
/// axis), x in the most significant bit of each triple. See Morton 1966; as used for LBVH by
/// Lauterbach et al. 2009 "Fast BVH Construction on GPUs".
#include "accel/core/geometry.h"

#include <algorithm>
#include <cassert>
#include <cstdint>

#if defined(__BMI2__)
#include <immintrin.h>
#endif

namespace arbor::accel {

/// Spreads the low 10 bits of v so that bit i lands on bit 3i (portable shifts and masks).
constexpr std::uint32_t morton_spread10(std::uint32_t v) {
    v &= 0x3ffu;
    v = (v | (v << 16)) & 0x030000ffu;
    v = (v | (v << 8)) & 0x0300f00fu;
    v = (v | (v << 4)) & 0x030c30c3u;
    v = (v | (v << 2)) & 0x09249249u;
    return v;
}

/// Spreads the low 21 bits of v so that bit i lands on bit 3i (portable shifts and masks).
constexpr std::uint64_t morton_spread21(std::uint64_t v) {
    v &= 0x1fffffull;
    v = (v | (v << 32)) & 0x001f00000000ffffull;
    v = (v | (v << 16)) & 0x001f0000ff0000ffull;
    v = (v | (v << 8)) & 0x100f00f00f00f00full;
    v = (v | (v << 4)) & 0x10c30c30c30c30c3ull;
    v = (v | (v << 2)) & 0x1249249249249249ull;
    return v;
}

/// 30-bit code of quantized coordinates (each < 1024; higher bits are ignored).
constexpr std::uint32_t morton_encode30_portable(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    return (morton_spread10(x) << 2) | (morton_spread10(y) << 1) | morton_spread10(z);
}

/// 63-bit code of quantized coordinates (each < 2^21; higher bits are ignored).
constexpr std::uint64_t morton_encode63_portable(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    return (morton_spread21(x) << 2) | (morton_spread21(y) << 1) | morton_spread21(z);
}

#if defined(__BMI2__)
/// The same codes through BMI2 pdep (one instruction per axis on this machine's CPUs).
inline std::uint32_t morton_encode30_pdep(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    return _pdep_u32(x, 0x24924924u) | _pdep_u32(y, 0x12492492u) | _pdep_u32(z, 0x09249249u);
}
inline std::uint64_t morton_encode63_pdep(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    return _pdep_u64(x, 0x4924924924924924ull) | _pdep_u64(y, 0x2492492492492492ull) |
           _pdep_u64(z, 0x1249249249249249ull);
}
#endif

inline std::uint32_t morton_encode30(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
#if defined(__BMI2__)
    return morton_encode30_pdep(x, y, z);
#else
    return morton_encode30_portable(x, y, z);
#endif
}

inline std::uint64_t morton_encode63(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
#if defined(__BMI2__)
    return morton_encode63_pdep(x, y, z);
#else
    return morton_encode63_portable(x, y, z);
#endif
}

/// Maps points of a box to integer cells [0, 2^bits - 1] per axis. Robust by construction:
/// - the arithmetic is in double, so boxes spanning +-FLT_MAX do not overflow;
/// - an axis of zero extent (or an empty box) maps every point to cell 0, with no division;
/// - points outside the box clamp to the first/last cell; NaN maps to 0 (never reaches a cast).
class MortonQuantizer {
public:
    /// bits_per_axis in 1..21: 10 for code30, 21 for code63.
    MortonQuantizer(const Bounds& box, int bits_per_axis)
        : bits_(std::clamp(bits_per_axis, 1, 21)), max_cell_(double((std::uint32_t(1) << bits_) - 1)) {
        const float lo[3] = {box.lo.x, box.lo.y, box.lo.z}, hi[3] = {box.hi.x, box.hi.y, box.hi.z};
        const double cells = double(std::uint32_t(1) << bits_);
        for (int a = 0; a < 3; ++a) {
            const double extent = double(hi[a]) - double(lo[a]);
            origin_[a] = box.empty() ? 0.0 : double(lo[a]);
            // extent > 0 is false for 0, negative (empty box) and NaN: those axes collapse to cell 0.
            scale_[a] = (!box.empty() && extent > 0.0) ? cells / extent : 0.0;
        }
    }

    /// Cell of coordinate v along axis a (0, 1, 2).
    std::uint32_t cell(float v, int a) const {
        const double c = (double(v) - origin_[a]) * scale_[a];
        // The last cell is closed at hi; written so that NaN (and anything not > 0) gives 0.
        return c > 0.0 ? std::uint32_t(std::min(c, max_cell_)) : 0u;
    }

    int bits() const { return bits_; }
    /// Codes of point p; code30 needs bits() == 10, code63 needs bits() == 21 (asserted).
    std::uint32_t code30(const Vec3f& p) const {
        assert(bits_ == 10);
        return morton_encode30(cell(p.x, 0), cell(p.y, 1), cell(p.z, 2));
    }
    std::uint64_t code63(const Vec3f& p) const {
        assert(bits_ == 21);
        return morton_encode63(cell(p.x, 0), cell(p.y, 1), cell(p.z, 2));
    }

private:
    int bits_;
    double origin_[3] = {0, 0, 0};
    double scale_[3] = {0, 0, 0};
    double max_cell_;
};

}  // namespace arbor::accel
