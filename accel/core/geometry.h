#pragma once
/// TriangleView: the input of every builder. Spans only, no ownership, no GLM.
#include "accel/core/ray.h"

#include <span>

namespace arbor::accel {

struct Bounds {
    Vec3f lo{std::numeric_limits<float>::infinity()};
    Vec3f hi{-std::numeric_limits<float>::infinity()};

    void grow(const Vec3f& p) { lo = simd::vmin(p, lo), hi = simd::vmax(p, hi); }
    void grow(const Bounds& b) { lo = simd::vmin(b.lo, lo), hi = simd::vmax(b.hi, hi); }
    bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
    Vec3f extent() const { return hi - lo; }
    Vec3f center() const { return (lo + hi) * 0.5f; }
    /// Surface area; computed in double so that boxes near FLT_MAX do not overflow to inf.
    double area() const {
        if (empty()) return 0.0;
        const double x = double(hi.x) - lo.x, y = double(hi.y) - lo.y, z = double(hi.z) - lo.z;
        return 2.0 * (x * y + y * z + z * x);
    }
    bool contains(const Bounds& b) const {
        return lo.x <= b.lo.x && lo.y <= b.lo.y && lo.z <= b.lo.z && hi.x >= b.hi.x && hi.y >= b.hi.y && hi.z >= b.hi.z;
    }
};

/// A triangle mesh as structure-of-arrays vertex positions and index triples. Triangle i is
/// (indices[3i], indices[3i+1], indices[3i+2]); its number i is the prim id reported in hits.
/// Indices must be < vertex count (the loader guarantees it).
struct TriangleView {
    std::span<const float> x, y, z;
    std::span<const std::uint32_t> indices;

    std::size_t triangle_count() const { return indices.size() / 3; }
    std::size_t vertex_count() const { return x.size(); }
    Vec3f vertex(std::uint32_t i) const { return {x[i], y[i], z[i]}; }
    Vec3f corner(std::size_t tri, int k) const { return vertex(indices[3 * tri + k]); }

    /// True when all three corners have finite coordinates. Non-finite triangles are dropped by
    /// every builder (and counted), so they are never hit.
    bool triangle_is_finite(std::size_t tri) const {
        for (int k = 0; k < 3; ++k) {
            const Vec3f p = corner(tri, k);
            if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) return false;
        }
        return true;
    }
    Bounds triangle_bounds(std::size_t tri) const {
        Bounds b;
        for (int k = 0; k < 3; ++k) b.grow(corner(tri, k));
        return b;
    }
};

}  // namespace arbor::accel
