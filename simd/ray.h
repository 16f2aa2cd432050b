#pragma once
/// Ray and Hit: the in-memory records of ../shared/spec/rayfile.md, byte for byte, and the one rule
/// that says which rays are traced at all (`traceable`, over a lane type T: every path, scalar,
/// single-ray SIMD and packet, applies this one template). They live here, below accel, so that
/// the SIMD kernels that load rays and store hits (ray_packet.h, wide_ray.h) use the same records
/// and the same rule; accel/core/ray.h gives them their accel names.
#include "simd/vec3.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace arbor::simd {

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

/// The rule every path applies before any work, per lane of T: a ray is traced only when its
/// origin and direction are finite, its direction is not zero, tnear and tfar are not NaN and
/// tnear <= tfar. Every other ray (NaN, Inf, zero-length, inactive) is a miss, found in O(1). A
/// direction whose components are all denormal (below FLT_MIN) counts as zero-length: 1/d
/// overflows on every axis, so neither the box test nor the triangle test (which divides by the
/// largest component) could follow it.
template <class T> inline Mask<T> traceable(const Vec3<T>& org, const Vec3<T>& dir, const T& tnear, const T& tfar) {
    const T min_normal(std::numeric_limits<float>::min());
    if constexpr (std::is_same_v<T, float>) {
        // The same rule spelled with && and || (a bool is no lane mask).
        return std::isfinite(org.x) && std::isfinite(org.y) && std::isfinite(org.z) && std::isfinite(dir.x) &&
               std::isfinite(dir.y) && std::isfinite(dir.z) &&
               (std::fabs(dir.x) >= min_normal || std::fabs(dir.y) >= min_normal || std::fabs(dir.z) >= min_normal) &&
               tnear <= tfar;  // NaN tnear/tfar fail the comparison
    } else {
        using xsimd::isfinite;
        return isfinite(org.x) & isfinite(org.y) & isfinite(org.z) & isfinite(dir.x) & isfinite(dir.y) & isfinite(dir.z) &
               ((vabs(dir.x) >= min_normal) | (vabs(dir.y) >= min_normal) | (vabs(dir.z) >= min_normal)) & (tnear <= tfar);
    }
}

/// The tie rule of every closest-hit query, per lane of T: a hit (t, prim) replaces the record
/// (best_t, best_prim) when its t is smaller, or equal with a lower prim (prims compared unsigned,
/// so the miss record {+inf, invalid_prim} loses to every hit: the triangle test gives no t of
/// +inf). The closest hit of a ray is thus one record, (the smallest t, the lowest prim at that t),
/// whatever the order in which a structure finds the candidates: every structure and path gives
/// brute force's answer, t, prim, u, v, bit for bit (u, v: the same test of the same triangle).
template <class T>
inline Mask<T> closer(const T& t, const IntOf<T>& prim, const T& best_t, const IntOf<T>& best_prim) {
    if constexpr (std::is_same_v<T, float>) {
        return t < best_t || (t == best_t && std::uint32_t(prim) < std::uint32_t(best_prim));
    } else {
        const IntOf<T> flip(std::numeric_limits<std::int32_t>::min());  // unsigned order from a signed compare
        return (t < best_t) | ((t == best_t) & xsimd::bool_cast((prim ^ flip) < (best_prim ^ flip)));
    }
}

/// The rule for one hit against a Hit record.
inline bool closer(float t, std::uint32_t prim, const Hit& best) {
    return closer<float>(t, std::int32_t(prim), best.t, std::int32_t(best.prim));
}

/// The rule for one Ray.
inline bool ray_is_traceable(const Ray& r) { return traceable<float>(r.org, r.dir, r.tnear, r.tfar); }

/// The agreement rule of rayfile.md: both miss, or both hit with |t1-t2| <= 1e-4 * max(1, |t1|).
inline bool hits_agree(const Hit& a, const Hit& b) {
    if (a.is_hit() != b.is_hit()) return false;
    if (!a.is_hit()) return true;
    return std::fabs(a.t - b.t) <= 1e-4f * std::max(1.0f, std::fabs(a.t));
}

}  // namespace arbor::simd
