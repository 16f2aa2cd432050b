#pragma once
/// Ray and Hit: the in-memory records of ../shared/spec/rayfile.md, byte for byte.
#include "simd/vec3.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace arbor::accel {

using simd::Vec3f;

/// A ray o + t*d for t in [tnear, tfar]; d need not be normalized. tfar < tnear means inactive.
struct Ray {
    Vec3f org;
    float tnear = 0.0f;
    Vec3f dir;
    float tfar = std::numeric_limits<float>::infinity();
};

inline constexpr std::uint32_t invalid_prim = 0xFFFFFFFFu;

/// Result of a query: t, triangle index, barycentrics (hit = (1-u-v) v0 + u v1 + v v2).
/// A miss is {+inf, invalid_prim, 0, 0}.
struct Hit {
    float t = std::numeric_limits<float>::infinity();
    std::uint32_t prim = invalid_prim;
    float u = 0.0f, v = 0.0f;

    bool is_hit() const { return prim != invalid_prim; }
};

inline constexpr Hit miss_hit{};

static_assert(sizeof(Ray) == 32 && offsetof(Ray, tnear) == 12 && offsetof(Ray, dir) == 16 && offsetof(Ray, tfar) == 28);
static_assert(sizeof(Hit) == 16 && offsetof(Hit, prim) == 4 && offsetof(Hit, u) == 8 && offsetof(Hit, v) == 12);

/// The rule every path applies before any work: a ray is traced only when its origin and direction
/// are finite, its direction is not zero, tnear and tfar are not NaN and tnear <= tfar. Every other
/// ray (NaN, Inf, zero-length, inactive) is a miss, found in O(1). A direction whose components are
/// all denormal (below FLT_MIN) counts as zero-length: 1/d overflows on every axis, so neither the
/// box test nor the triangle test (which divides by the largest component) could follow it.
inline bool ray_is_traceable(const Ray& r) {
    const bool finite = std::isfinite(r.org.x) && std::isfinite(r.org.y) && std::isfinite(r.org.z) &&
                        std::isfinite(r.dir.x) && std::isfinite(r.dir.y) && std::isfinite(r.dir.z);
    constexpr float min_normal = std::numeric_limits<float>::min();
    const bool nonzero = std::fabs(r.dir.x) >= min_normal || std::fabs(r.dir.y) >= min_normal || std::fabs(r.dir.z) >= min_normal;
    return finite && nonzero && r.tnear <= r.tfar;  // NaN tnear/tfar fail the comparison
}

/// The agreement rule of rayfile.md: both miss, or both hit with |t1-t2| <= 1e-4 * max(1, |t1|).
inline bool hits_agree(const Hit& a, const Hit& b) {
    if (a.is_hit() != b.is_hit()) return false;
    if (!a.is_hit()) return true;
    return std::fabs(a.t - b.t) <= 1e-4f * std::max(1.0f, std::fabs(a.t));
}

}  // namespace arbor::accel
