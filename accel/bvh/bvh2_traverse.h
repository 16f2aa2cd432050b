#pragma once
/// The one scalar traversal loop of Bvh2Layout, for closest hit and any hit (template<bool AnyHit>),
/// with the leaf work passed in. Distance-ordered: of two hit children the nearer is visited first
/// and the farther is pushed with its entry distance; a popped entry farther than the current tfar
/// is skipped. Box tests are simd::slab_test (Ize 2013, with its zero-direction rule) exactly,
/// against simd::box_tfar(tfar) (room for a triangle's t rounded below its box's entry).
#include "accel/bvh/bvh2_layout.h"
#include "simd/ray_box.h"

#include <span>

namespace arbor::accel {

/// A deferred child: reference (as in Bvh2Node::child/count) and its box entry distance.
struct Bvh2StackEntry {
    std::uint32_t child, count;
    float t;
};

/// Stack entries a traversal of `layout` may need.
inline std::size_t bvh2_stack_size(const Bvh2Layout& layout) { return std::size_t(layout.max_depth) + 1; }

/// No-op node hook of traverse_bvh2.
struct NoNodeHook {
    void operator()() const {}
};

/// Walks `layout` for the ray (org, dir, tnear, tfar). `tfar` is read after every leaf, so the leaf
/// work shortens the ray by lowering it. `leaf(first_slot, count)` tests triangle slots
/// [first_slot, first_slot + count) and returns true when it found a hit; with AnyHit that ends
/// the walk. `node_hook()` is called for every interior node whose child boxes are tested (the
/// statistics mode counts with it; the default does nothing and compiles away). `stack` must hold
/// bvh2_stack_size(layout) entries. The caller checks ray_is_traceable first.
template <bool AnyHit, class LeafFn, class NodeHook = NoNodeHook>
inline void traverse_bvh2(const Bvh2Layout& layout, const Vec3f& org, const Vec3f& dir, float tnear, float& tfar,
                          std::span<Bvh2StackEntry> stack, LeafFn&& leaf, NodeHook&& node_hook = {}) {
    if (layout.empty()) return;
    const simd::SlabRay r = simd::slab_ray(org, dir);
    // What the boxes are culled against: worked out again after a leaf that found a hit.
    float tbox = simd::box_tfar(tfar);
    float t_entry;
    if (!simd::slab_test(r, layout.root_box.lo, layout.root_box.hi, tnear, tbox, t_entry)) return;
    // Offsets of the near planes in Bvh2Node::x/y/z (0: lo, 2: hi); the far planes are at 2 - near.
    const int nx = 2 * r.near_is_hi[0], ny = 2 * r.near_is_hi[1], nz = 2 * r.near_is_hi[2];
    const Bvh2Node* nodes = layout.nodes.data();
    std::size_t sp = 0;
    std::uint32_t child = layout.root_child, count = layout.root_count;
    for (;;) {
        if (count != 0) {
            if (leaf(child, count)) {
                if constexpr (AnyHit) return;
                tbox = simd::box_tfar(tfar);
            }
        } else {
            const Bvh2Node& n = nodes[child];
            node_hook();
            float t[2];
            bool hit[2];
            for (int c = 0; c < 2; ++c) {
                const Vec3f near_plane{n.x[nx + c], n.y[ny + c], n.z[nz + c]};
                const Vec3f far_plane{n.x[2 - nx + c], n.y[2 - ny + c], n.z[2 - nz + c]};
                hit[c] = simd::slab_test<float>(near_plane, far_plane, r.org, r.rcp_near, r.rcp_far, tnear, tbox, t[c]);
            }
            if (hit[0] && hit[1]) {
                const int first = t[1] < t[0] ? 1 : 0, second = 1 - first;
                stack[sp++] = {n.child[second], n.count[second], t[second]};
                child = n.child[first], count = n.count[first];
                continue;
            }
            if (hit[0] || hit[1]) {
                const int c = hit[0] ? 0 : 1;
                child = n.child[c], count = n.count[c];
                continue;
            }
        }
        // Pop the nearest deferred child that can still hold a hit within [tnear, tfar].
        for (;;) {
            if (sp == 0) return;
            const Bvh2StackEntry& e = stack[--sp];
            if (simd::slab_accept(e.t, tbox)) {  // slab_test's rule: room for a negative tfar
                child = e.child, count = e.count;
                break;
            }
        }
    }
}

}  // namespace arbor::accel
