#pragma once
/// The top level of a two-level scene: BVHs over the instances' world boxes (one item per
/// instance), built by object median on the longest axis of the centroids. Small (about one node
/// per instance) and walked once per ray or point.
///   - Rays walk a wide tree, as many children per node as the widest float lanes of this
///     compilation (simd::FloatV: 16 with AVX-512, 8 with AVX2, 4 in a portable build), its child
///     boxes tested at once by the slab test of the bottom structures' SIMD paths
///     (simd/ray_box.h: conservative, Ize's padded far planes, so a box the ray meets is never lost
///     to rounding). The tree's shape changes which boxes are tested, never which items are met.
///   - Points walk a binary tree in double precision, nearest box first.
#include <bit>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "accel/core/geometry.h"
#include "simd/box_kernels.h"
#include "simd/ray_box.h"

namespace arbor::accel {

class TopBvh {
public:
    /// Builds over `boxes` (item i = boxes[i]); items with an empty box are left out.
    static TopBvh build(std::span<const Bounds> boxes);

    /// Calls f(item, t_enter) for every item whose box the segment o + t d, t in [tnear, tfar],
    /// meets (the ray given by its slab constants, simd::slab_ray; tnear <= tfar), t_enter being
    /// where the segment enters the box, rounded down: at most the exact entry distance. `plain`:
    /// simd::is_plain holds for the ray (then the shorter slab_test_plain, with the same answers).
    template <class F>
    void ray_items(const simd::SlabRay& r, float tnear, float tfar, bool plain, F&& f) const;

    /// Calls f(item, box_distance2) for items nearest box first; stops at boxes farther than
    /// sqrt(reach2), which f may lower as it finds closer answers.
    template <class F>
    void nearest_items(const double p[3], double& reach2, F&& f) const;

    std::size_t memory_bytes() const {
        return nodes_.size() * sizeof(Node) + wide_.size() * sizeof(Wide) + items_.size() * sizeof(std::uint32_t);
    }
    bool empty() const { return nodes_.empty(); }

private:
    struct Node {
        Bounds box;
        std::uint32_t first = 0, count = 0;  ///< a leaf: items_[first, first + count)
        std::uint32_t right = 0;             ///< an interior node: children at this + 1 and `right`
    };
    using Lane = simd::FloatV;
    static constexpr std::uint32_t width = std::uint32_t(Lane::size);
    static_assert(std::has_single_bit(width));
    /// A node of the rays' tree: `width` child boxes (unused slots empty, which never hit) and per
    /// child either a node index or, with `item_bit`, an item.
    struct Wide {
        simd::BoxesSoA<width> box;
        std::uint32_t child[width] = {};
    };
    static constexpr std::uint32_t item_bit = 0x80000000u;
    /// Stack bound of the rays' walk: the tree's median splits make it at most 33 levels deep
    /// (2^32 items, at least 2-way), and a walk holds fewer than `width` entries per level.
    static constexpr int wide_stack = 33 * int(width);

    static double dist2(const Bounds& b, const double p[3]) {
        double s = 0.0;
        for (int k = 0; k < 3; ++k) {
            const double lo = b.lo[k], hi = b.hi[k];
            const double e = p[k] < lo ? lo - p[k] : (p[k] > hi ? p[k] - hi : 0.0);
            s += e * e;
        }
        return s;
    }
    std::uint32_t build_node(std::span<const Bounds> boxes, std::uint32_t first, std::uint32_t count);
    std::uint32_t build_wide(std::span<const Bounds> boxes, std::vector<std::uint32_t>& items, std::uint32_t first,
                             std::uint32_t count);

    std::vector<Node> nodes_;
    std::vector<Wide> wide_;
    std::vector<std::uint32_t> items_;
};

template <class F>
void TopBvh::ray_items(const simd::SlabRay& r, float tnear, float tfar, bool plain, F&& f) const {
    if (wide_.empty()) return;
    using T = Lane;
    const simd::Vec3<T> org(T(r.org.x), T(r.org.y), T(r.org.z));
    const simd::Vec3<T> rn(T(r.rcp_near.x), T(r.rcp_near.y), T(r.rcp_near.z));
    const simd::Vec3<T> rf(T(r.rcp_far.x), T(r.rcp_far.y), T(r.rcp_far.z));
    // (Against box_tfar of the ray's tfar, ray_box.h: a bottom's triangle at t <= tfar may lie on a
    // placement's box where its computed entry rounds above tfar.)
    const T tn(tnear), tf(simd::box_tfar(tfar));
    std::uint32_t stack[wide_stack];
    int top = 0;
    stack[top++] = 0;
    alignas(64) float enter[width];
    while (top > 0) {
        const Wide& n = wide_[stack[--top]];
        simd::Vec3<T> np, fp;
        for (int k = 0; k < 3; ++k) {
            np[k] = T::load_aligned(n.box.b[r.near_is_hi[k]][k]);
            fp[k] = T::load_aligned(n.box.b[1 - r.near_is_hi[k]][k]);
        }
        T t_entry;
        std::uint32_t bits = simd::to_bits(plain ? simd::slab_test_plain<T>(np, fp, org, rn, rf, tn, tf, t_entry)
                                                 : simd::slab_test<T>(np, fp, org, rn, rf, tn, tf, t_entry));
        if (bits == 0) continue;
        t_entry.store_aligned(enter);
        for (; bits != 0; bits &= bits - 1) {
            const int i = std::countr_zero(bits);
            const std::uint32_t c = n.child[i];
            if (c & item_bit) {
                // Down by 2^-20 of its size: the float slab distance may round up by a few ulps.
                const float t = enter[i];
                f(c & ~item_bit, double(t) - 0x1p-20 * std::fabs(double(t)));
            } else {
                stack[top++] = c;
            }
        }
    }
}

template <class F>
void TopBvh::nearest_items(const double p[3], double& reach2, F&& f) const {
    if (nodes_.empty()) return;
    struct Entry {
        std::uint32_t node;
        double d2;
    };
    Entry stack[64];
    int top = 0;
    stack[top++] = {0, dist2(nodes_[0].box, p)};
    while (top > 0) {
        const Entry e = stack[--top];
        if (e.d2 > reach2) continue;
        const Node& n = nodes_[e.node];
        if (n.count > 0) {
            for (std::uint32_t i = 0; i < n.count; ++i) {
                const std::uint32_t item = items_[n.first + i];
                f(item);
            }
            continue;
        }
        // The nearer child is walked first (pushed last).
        const std::uint32_t a = e.node + 1, b = n.right;
        const double da = dist2(nodes_[a].box, p), db = dist2(nodes_[b].box, p);
        if (da <= db) {
            stack[top++] = {b, db};
            stack[top++] = {a, da};
        } else {
            stack[top++] = {a, da};
            stack[top++] = {b, db};
        }
    }
}

}  // namespace arbor::accel
