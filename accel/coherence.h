#pragma once
/// A cheap coherence measure of a batch of rays, for TracePath::best: packets pay off when the
/// rays that would share a packet go the same way from nearly the same place (primary rays of an
/// image tile, shadow rays from a tile towards one light) and lose when they do not (diffuse
/// bounces, random rays). It looks at each group of `group` consecutive rays, as the packet path
/// would pack them, and costs a few operations per ray (~1% of a traversal).
#include "accel/ray.h"

#include <cmath>
#include <span>

namespace arbor::accel {

/// Fraction (0..1) of the groups of `group` consecutive rays in which every traceable ray has the
/// same direction octant (sign bits of d, so -0 counts as negative, as in the slab test) and the
/// origins lie within `spread` of each other on every axis. Groups without traceable rays do
/// not count; a batch without any gives 0.
inline double coherent_fraction(std::span<const Ray> rays, std::size_t group, float spread) {
    std::size_t groups = 0, coherent = 0;
    for (std::size_t base = 0; base < rays.size(); base += group) {
        const std::size_t end = std::min(rays.size(), base + group);
        bool first = true, ok = true;
        unsigned octant = 0;
        Vec3f lo, hi;
        for (std::size_t i = base; i < end && ok; ++i) {
            const Ray& r = rays[i];
            if (!ray_is_traceable(r)) continue;
            const unsigned o = unsigned(std::signbit(r.dir.x)) | unsigned(std::signbit(r.dir.y)) << 1 |
                               unsigned(std::signbit(r.dir.z)) << 2;
            if (first) {
                octant = o, lo = hi = r.org, first = false;
                continue;
            }
            lo = simd::vmin(r.org, lo), hi = simd::vmax(r.org, hi);
            ok = o == octant && hi.x - lo.x <= spread && hi.y - lo.y <= spread && hi.z - lo.z <= spread;
        }
        if (first) continue;
        ++groups;
        coherent += ok;
    }
    return groups ? double(coherent) / double(groups) : 0.0;
}

}  // namespace arbor::accel
