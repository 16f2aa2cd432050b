#pragma once
/// Front-to-back stack walk of the kd-tree (the recursive ray traversal of Havran's thesis, 2000,
/// "TA_rec_B", in Wald's 2004 formulation): at an interior node the child on the side the ray comes
/// from is walked first, the other one is pushed with the rest of the ray's interval; a closest-hit
/// walk skips a pushed subtree whose interval starts beyond the best hit. Any-hit queries walk with
/// it on every path (the packet path in its packet form, kdtree_stack_packet.h, which keeps each
/// lane's leaf order, hence the first hit); closest hit follows the ropes (kdtree_traverse.h),
/// 1.2-1.3x faster per ray.
///
/// How it stays exact (the same guarantee as the rope walk of kdtree_traverse.h, by other means):
/// - Plane crossings t = (p - o) / d are computed in double (p - o is exact for floats), about one
///   rounding each.
/// - The sides of a plane are chosen from the box of the ray's current interval (the piece of the
///   ray in the subtree), which changes only where both sides are walked: one float compare per
///   node on the walk's critical path. Every interval is widened at each plane by e_k = point_tolerance * max|d| * T / |d_k| in t (T:
///   the largest |t| of the ray's clipped segment), the rope walk's point tolerance: a subtree is
///   walked when the ray passes within point_tolerance * max|d| * T of its cell in every axis. The
///   watertight test, deciding in the ray's sheared float frame, may "hit" a triangle whose cells
///   the ray passes a hair away from (near a vertex or edge); such cells are within that tolerance,
///   so every triangle the test hits is offered. Leaves near a plane are thus walked by both
///   sides' intervals (a leaf is still walked at most once).
/// - A hit is accepted wherever it lies in [tnear, current best]. A closest-hit walk skips a
///   subtree only when its (widened) interval starts strictly after the best hit, so a triangle
///   tied at that t in another cell is still offered and the tie rule (lowest prim) holds.
/// - Zero direction components (1/+-0 = +-inf): on that axis the ray's box is its origin, so it
///   walks the side the origin is on, and both sides when the origin lies in the plane. The
///   tolerance of such an axis is 0 (the triangle test is exact in sign there).
#include "accel/kdtree/kdtree_node.h"
#include "accel/kdtree/kdtree_traverse.h"
#include "accel/kdtree/kdtree_walk_dir.h"
#include "accel/core/ray.h"
#include "simd/simd.h"

#include <algorithm>
#include <cmath>

namespace arbor::accel::kd {

/// A pushed subtree and the ray's interval in it.
struct StackEntry {
    std::uint32_t node;
    double tmin, tmax;
};

/// One ray's walk: per-ray constants, the subtree being walked, the ray's interval [tmin, tmax]
/// in it with the box of that piece of the ray (widened by the tolerance), and the pushed subtrees.
struct StackWalk {
    double o[3], d[3];
    double rcp[3];   ///< 1 / d in double; +-inf for d = +-0
    double e[3];     ///< the widening of an interval at a plane of axis k (0 on flat axes)
    bool neg[3];     ///< sign bit of d set: the ray comes from the upper side (right child first)
    bool flat[3];    ///< d == +-0
    float lo[3] = {}, hi[3] = {};  ///< the ray's points over [tmin - e, tmax + e], rounded to float
    std::uint32_t node;
    double tmin, tmax;
    int sp;
    StackEntry stack[kd_max_depth + 1];
};

/// Sets the interval [tmin, tmax] and its box. The box decides the sides at a plane (a side is
/// walked when the box reaches it); it changes only where both sides are walked. Rounding to
/// float is monotone and splits are floats, so a split inside the double box is inside the float
/// box: the float box walks at least the subtrees the double one would.
ARBOR_INLINE void stack_interval(StackWalk& w, double tmin, double tmax) {
    w.tmin = tmin, w.tmax = tmax;
    for (int k = 0; k < 3; ++k) {
        if (w.flat[k]) continue;  // lo = hi = the origin, set once
        const double a = w.o[k] + (tmin - w.e[k]) * w.d[k], b = w.o[k] + (tmax + w.e[k]) * w.d[k];
        w.lo[k] = float(w.neg[k] ? b : a);
        w.hi[k] = float(w.neg[k] ? a : b);
    }
}

/// Sets up the walk of ray `r` (traceable) from the root. False when the ray passes the scene box
/// farther than the tolerance (nothing to visit).
inline bool stack_start(const KdTree& tree, const Ray& r, StackWalk& w) {
    const Vec3f dir = walk_direction(r.dir);
    const double dmax = std::max({std::fabs(double(dir.x)), std::fabs(double(dir.y)), std::fabs(double(dir.z))});
    double enter[3], leave[3];
    double t0 = r.tnear, t1 = r.tfar;
    for (int k = 0; k < 3; ++k) {
        w.o[k] = r.org[k];
        w.d[k] = dir[k];
        w.neg[k] = std::signbit(dir[k]);
        w.flat[k] = dir[k] == 0.0f;
        w.rcp[k] = 1.0 / double(dir[k]);
        w.e[k] = 0.0;
        if (w.flat[k]) {
            if (!flat_axis_can_hit(r.org[k], tree.box.lo[k], tree.box.hi[k])) return false;
            w.lo[k] = w.hi[k] = r.org[k];
            continue;
        }
        const double a = (double(tree.box.lo[k]) - w.o[k]) * w.rcp[k];
        const double b = (double(tree.box.hi[k]) - w.o[k]) * w.rcp[k];
        // min and max, not a branch on the sign of d (rope_start): a <= b exactly when d > 0.
        enter[k] = std::min(a, b);
        leave[k] = std::max(a, b);
        t0 = std::max(t0, enter[k]);
        t1 = std::min(t1, leave[k]);
    }
    // T bounds |t| over the segment (and a hair beyond it): the scale of the tolerance.
    const double scale = std::max(std::fabs(t0), std::fabs(t1));
    t0 = r.tnear, t1 = r.tfar;
    for (int k = 0; k < 3; ++k) {
        if (w.flat[k]) continue;
        w.e[k] = point_tolerance * dmax * std::fabs(w.rcp[k]) * scale;
        t0 = std::max(t0, enter[k] - w.e[k]);
        t1 = std::min(t1, leave[k] + w.e[k]);
    }
    if (!(t0 <= t1)) return false;
    w.node = 0, w.sp = 0;
    stack_interval(w, t0, t1);
    return true;
}

/// From w.node down to a leaf along [w.tmin, w.tmax], pushing the far children that the interval
/// reaches; returns the leaf's index. Count: adds the interior nodes passed to `visited`.
template <bool Count = false>
ARBOR_INLINE std::uint32_t stack_descend(const KdNode* nodes, StackWalk& w, std::uint64_t& visited) {
    std::uint32_t node = w.node;
    KdNode n = nodes[node];
    while (!n.is_leaf()) {
        if constexpr (Count) ++visited;
        const int k = n.axis();
        const std::uint32_t lo = node + 1, hi = n.index();
        const bool to_lo = w.lo[k] <= n.split, to_hi = w.hi[k] >= n.split;
        if (to_lo & to_hi) {
            // Both sides: the near one now with the interval up to the plane (+ e), the far one
            // pushed with the rest (from the plane - e). A NaN crossing (origin in the plane of a
            // flat axis) leaves both intervals whole (std::min/max keep their first argument).
            const double ts = (double(n.split) - w.o[k]) * w.rcp[k];
            w.stack[w.sp++] = {w.neg[k] ? lo : hi, std::max(w.tmin, ts - w.e[k]), w.tmax};
            stack_interval(w, w.tmin, std::min(w.tmax, ts + w.e[k]));
            node = w.neg[k] ? hi : lo;
        } else {
            node = to_lo ? lo : hi;
        }
        n = nodes[node];
    }
    w.node = node;
    return n.index();
}

/// After a leaf: takes the next pushed subtree to walk. Closest hit (`best_t`: the best hit so
/// far, +inf while none): subtrees starting beyond best_t are dropped and intervals end at best_t.
/// False when the walk is over.
template <bool AnyHit> ARBOR_INLINE bool stack_pop(StackWalk& w, float best_t) {
    const double best = best_t;
    while (w.sp > 0) {
        const StackEntry& s = w.stack[--w.sp];
        if (!AnyHit && s.tmin > best) continue;
        w.node = s.node;
        stack_interval(w, s.tmin, AnyHit ? s.tmax : std::min(s.tmax, best));
        return true;
    }
    return false;
}

/// Walks the leaves ray `r` passes, front to back, calling leaf_fn(leaf index) -> bool (true:
/// stop, for any hit). For closest hit, `best_t` is the distance of the best hit so far (+inf
/// while none), updated by leaf_fn. Untraceable rays and an empty tree visit nothing; a leaf is
/// visited at most once. Count: adds the interior nodes passed to `visited`.
template <bool AnyHit, bool Count = false, class LeafFn>
void walk_stack(const KdTree& tree, const Ray& r, const float& best_t, LeafFn&& leaf_fn, std::uint64_t& visited) {
    if (tree.empty() || !ray_is_traceable(r)) return;
    StackWalk w;
    if (!stack_start(tree, r, w)) return;
    const KdNode* nodes = tree.nodes.data();
    do {
        if (leaf_fn(stack_descend<Count>(nodes, w, visited))) return;
    } while (stack_pop<AnyHit>(w, best_t));
}

}  // namespace arbor::accel::kd
