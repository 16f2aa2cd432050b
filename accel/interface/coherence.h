#pragma once
/// A cheap coherence measure of a batch of rays, for TracePath::best: packets pay off when the
/// rays that would share a packet go the same way from nearly the same place (primary rays of an
/// image tile, shadow rays from a tile towards one light), and, as long as their lanes soon go on
/// alone, when they only start from nearly the same place (diffuse bounces from a tile: the
/// packet shares the top of the tree); they lose when the origins are scattered (random rays). It
/// looks at groups of `group` consecutive rays, as the packet path would pack them: at most
/// `max_groups` of them, spread evenly over the batch (looking at every group cost ~10% of the
/// packet path's time on primary rays; 8 groups of a 1024-ray chunk, ~1%).
#include "accel/core/ray.h"

#include <algorithm>
#include <cmath>
#include <span>

namespace arbor::accel {

/// Fraction (0..1) of the sampled groups of `group` consecutive rays in which every traceable ray
/// has the same direction octant (sign bits of d, so -0 counts as negative, as in the slab test;
/// not asked when `same_octant` is false) and the origins lie within `spread` of each other on
/// every axis. Groups without traceable rays do not count; a batch without any gives 0.
/// Deterministic (the sample depends on the sizes only).
/// Rays from the start of one sampled group to the next for a batch of `n` rays: the sample is the
/// groups starting at 0, step, 2 step, ... (each `group` rays, the last one possibly cut by n).
inline std::size_t coherence_sample_step(std::size_t n, std::size_t group, std::size_t max_groups = 8) {
    group = std::max<std::size_t>(group, 1);
    const std::size_t all = (n + group - 1) / group;
    return group * std::max<std::size_t>(1, (all + max_groups - 1) / std::max<std::size_t>(max_groups, 1));
}

inline double coherent_fraction(std::span<const Ray> rays, std::size_t group, float spread, std::size_t max_groups = 8,
                                bool same_octant = true) {
    group = std::max<std::size_t>(group, 1);
    const std::size_t step = coherence_sample_step(rays.size(), group, max_groups);
    std::size_t groups = 0, coherent = 0;
    for (std::size_t base = 0; base < rays.size(); base += step) {
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
            ok = (o == octant || !same_octant) && hi.x - lo.x <= spread && hi.y - lo.y <= spread && hi.z - lo.z <= spread;
        }
        if (first) continue;
        ++groups;
        coherent += ok;
    }
    return groups ? double(coherent) / double(groups) : 0.0;
}

}  // namespace arbor::accel
