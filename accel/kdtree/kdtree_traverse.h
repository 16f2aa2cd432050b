#pragma once
/// Stackless kd-tree traversal along the leaves' ropes (Popov, Günther, Seidel, Slusallek 2007):
/// one walk for closest and any hit (template<bool AnyHit>), the leaf work passed in.
///
/// How it stays exact where kd-trees usually leak:
/// - Plane crossings t = (p - o) / d are computed in double: p - o is exact for floats, so every
///   crossing has about one double rounding. The walk follows these crossings exactly (a crossing
///   at exactly t goes to the side the ray moves into), so it is a partition of the ray into leaf
///   intervals; no leaf is skipped for being thinner than a float ulp of t. The node and face
///   decisions are those of the double crossings, but taken by one float compare against a window
///   around the ray's point (point_window) wherever the plane is clearly away from it; only planes
///   inside the window (within the tolerance, or a few float ulps more) compute their crossing.
/// - A hit is accepted wherever it lies (t in [tnear, current tfar]); a closest-hit walk stops
///   after a leaf only when its best hit is not beyond that leaf's exit. So a triangle spanning
///   several leaves is never lost at a leaf face, and the closest hit is the true closest.
/// - The watertight triangle test decides in the ray's sheared float frame, i.e. for triangles
///   moved by a few float ulps of their distance to the origin; a ray aimed at a vertex may be
///   "hit" by a triangle whose leaves it passes a hair away from. So wherever the walk crosses a
///   face within `point_tolerance` (relative to the distance travelled) of another plane of the
///   leaf arrangement (near an edge or corner; also an origin on a split plane), every leaf within
///   that tolerance of the crossing point is tested too (visit_point). The walk itself goes on.
/// - Zero direction components (ray_box.h's rule: 1/+-0 = +-inf, the sign bit picks the side): the
///   ray never crosses planes of that axis. A ray lying exactly in a split plane walks the side its
///   sign bit picks; if a visited leaf has a face in the ray's plane, the walk is repeated with the
///   other side(s), so triangles touching the plane from either side are found. (On such an axis
///   the triangle test is exact in sign, so no tolerance is needed there.)
#include "accel/kdtree/kdtree_node.h"
#include "accel/kdtree/kdtree_walk_dir.h"
#include "accel/core/ray.h"

#include <algorithm>
#include <cmath>

namespace arbor::accel::kd {

/// A crossing point closer than this times the distance travelled (|t| * max|d|) to another plane
/// counts as lying on it. The sheared watertight test moves corners by at most ~6 float ulps of
/// that distance (2^-21.4); this is 8 times more.
inline constexpr double point_tolerance = 0x1p-18;

/// Per-ray constants of the walk.
struct RopeRay {
    double o[3];
    double d[3];
    double rcp[3];        ///< 1 / d in double; +-inf for d = +-0
    double dmax;          ///< max|d|
    double tol[3];        ///< point_tolerance * max|d| / |d[k]|: the tolerance in t, per unit of t
    bool up[3];           ///< sign bit of d clear: moving towards larger coordinates
    bool flat[3];         ///< d == +-0: the ray never crosses planes of this axis
    bool tie_right[3];    ///< flat axes: the side walked when the ray lies in a split plane
    double t_end;         ///< min(tfar, scene exit)
};

inline double cross_t(const RopeRay& s, int k, float p) { return (double(p) - s.o[k]) * s.rcp[k]; }
/// Whether the ray at distance t is within the point tolerance of the plane it crosses at tp.
inline bool near_plane(const RopeRay& s, int k, double tp, double t) { return std::fabs(tp - t) <= s.tol[k] * std::fabs(t); }

/// The side of the split plane `split` of axis k where the ray is just after distance t, as the
/// double crossing decides it: a crossing at exactly t goes to the side the ray moves into, flat
/// axes compare the origin (tie: tie_right). Sets `near` when the point at t is within the
/// tolerance of the plane. True: the right (upper) child.
inline bool side_exact(const RopeRay& s, int k, float split, double t, bool& near) {
    if (s.flat[k]) return s.o[k] > split || (s.o[k] == split && s.tie_right[k]);
    const double tp = cross_t(s, k, split);
    near |= near_plane(s, k, tp, t);
    return tp == t ? s.up[k] : (t > tp) == s.up[k];
}

/// descend's reference: side_exact at every node (the walk before the float window; kept for the
/// test that the window takes the same decisions).
template <bool Count = false>
inline std::uint32_t descend_exact(const KdNode* nodes, const RopeRay& s, std::uint32_t node, double t, bool& near,
                                   std::uint64_t& visited) {
    for (;;) {
        const KdNode n = nodes[node];
        if (n.is_leaf()) return node;
        if constexpr (Count) ++visited;
        node = side_exact(s, n.axis(), n.split, t, near) ? n.index() : node + 1;
    }
}

/// Where the ray's point at distance t is, in float, with the margin of side_exact's tolerance: a
/// split of axis k below lo[k] has the point clearly on its right side and not near it, a split
/// above hi[k] clearly on its left side; only splits in [lo[k], hi[k]] need side_exact.
///
/// Why: side_exact's crossing tp = fl(fl(split - o) * fl(1 / d)) is (split - o) / d times (1 + a)
/// with |a| <= 3.01 u (u = 2^-53), its tolerance tol_k |t| is at most
/// point_tolerance * max|d| / |d_k| * |t| * (1 + 3.01 u), and t - (split - o) / d = (p - split) / d
/// with p = o + t d the exact point. Working through the two compares, near_plane is false and
/// (t > tp) == up equals p > split whenever |p - split| > (point_tolerance * max|d| + 3.02 u |d_k|)
/// * |t| * (1 + 8 u), which m = point_tolerance * max|d| * |t| * (1 + 2^-20) exceeds (u / 2^-18 =
/// 2^-35). The point is computed in double (error <= 2.01 u (|o| + |t d|)) and the window is
/// p -+ R with R = m (1 + 2^-21) + (|o| + |t d|) 2^-21, rounded to float (which moves a value by at
/// most 2^-24 of it, |p -+ R| <= |o| + |t d| + R): R covers the point's error and the rounding, so
/// lo[k] <= p - m and hi[k] >= p + m. R does not depend on p, so the window is two roundings after
/// the point. Flat axes: lo = hi = the origin (a float), which is side_exact's compare without the
/// tie. NaN windows (t infinite) decide nothing: every split goes to side_exact.
struct PointWindow {
    float lo[3], hi[3];
};
inline PointWindow point_window(const RopeRay& s, double t) {
    PointWindow w;
    const double at = std::fabs(t);
    const double m = point_tolerance * s.dmax * at * (1.0 + 0x1p-20);
    for (int k = 0; k < 3; ++k) {
        if (s.flat[k]) {
            w.lo[k] = w.hi[k] = float(s.o[k]);
            continue;
        }
        const double p = s.o[k] + t * s.d[k];
        const double r = m * (1.0 + 0x1p-21) + (std::fabs(s.o[k]) + at * std::fabs(s.d[k])) * 0x1p-21;
        w.lo[k] = float(p - r);
        w.hi[k] = float(p + r);
    }
    return w;
}

/// From `node` down to the leaf the ray is in just after distance t, taking side_exact's decision
/// at every node (a crossing at exactly t goes to the side the ray moves into, flat axes compare
/// the origin, tie: tie_right): one float compare against the point window per node, side_exact
/// only for splits inside the window. Sets `near` when the point at t is within the tolerance of a
/// split plane on the way. Count: adds the interior nodes passed to `visited`.
/// `w`: point_window(s, t).
template <bool Count = false>
inline std::uint32_t descend(const KdNode* nodes, const RopeRay& s, std::uint32_t node, double t, const PointWindow& w,
                             bool& near, std::uint64_t& visited) {
    for (;;) {
        const KdNode n = nodes[node];
        if (n.is_leaf()) return node;
        if constexpr (Count) ++visited;
        const int k = n.axis();
        bool right = n.split < w.lo[k];
        if (!(right || n.split > w.hi[k])) [[unlikely]]
            right = side_exact(s, k, n.split, t, near);
        node = right ? n.index() : node + 1;
    }
}

/// Calls leaf_fn for every leaf whose closed box, grown by the point tolerance, holds the ray's
/// point at distance t, except leaf `tested` (a leaf index, or kd_no_rope for none): the leaf the
/// walk has just tested in full with the same ray, whose triangles a second test would offer again
/// with the same answers (no better hit for closest hit; none at all for any hit, which would have
/// stopped). Random rays on flat models (every origin in the model's plane, every ray leaving the
/// scene box at once, near its face) tested their first leaf twice. Returns true when leaf_fn asks
/// to stop.
template <bool Count, class LeafFn>
bool visit_point(const KdNode* nodes, const RopeRay& s, double t, LeafFn& leaf_fn, std::uint64_t& visited,
                 std::uint32_t tested = kd_no_rope) {
    std::uint32_t stack[kd_max_depth + 2];
    int sp = 0;
    std::uint32_t node = 0;
    for (;;) {
        const KdNode n = nodes[node];
        if (n.is_leaf()) {
            if (n.index() != tested && leaf_fn(n.index())) return true;
            if (sp == 0) return false;
            node = stack[--sp];
            continue;
        }
        if constexpr (Count) ++visited;
        const int k = n.axis();
        bool left, right;
        if (s.flat[k]) {
            left = s.o[k] <= n.split;
            right = s.o[k] >= n.split;
        } else {
            const double tp = cross_t(s, k, n.split);
            const bool both = near_plane(s, k, tp, t);
            right = both || (t > tp) == s.up[k];
            left = both || !right;
        }
        if (left && right) stack[sp++] = n.index();
        node = left ? node + 1 : n.index();
    }
}

/// Whether the point window `w` lies strictly between the split planes that bound `leaf`, in every
/// axis: a face with a rope is such a plane (the ropes are passed down from the root, and a face
/// gets one exactly at the split that made it), a face without one (on the scene box) has no split
/// behind it. Then every split on the way from the root to the leaf lies outside the window, and
/// visit_point at the window's distance takes one side at each (point_window), i.e. visits this
/// leaf alone.
inline bool window_inside_leaf(const KdLeaf& leaf, const PointWindow& w) {
    bool inside = true;
    for (int k = 0; k < 3; ++k) {
        inside &= leaf.rope[kd_face(k, false)] == kd_no_rope || leaf.box.lo[k] < w.lo[k];
        inside &= leaf.rope[kd_face(k, true)] == kd_no_rope || w.hi[k] < leaf.box.hi[k];
    }
    return inside;
}

/// What a step of the walk ended with.
enum class RopeStep { end, leaf, stop };  ///< the pass is over; `node` is the next leaf; leaf_fn stopped it

/// The first leaf of a pass from distance t0: `node` is set to it (RopeStep::leaf), unless a
/// visit_point around the start stopped the walk (RopeStep::stop).
template <bool Count, class LeafFn>
RopeStep rope_first(const KdTree& tree, const RopeRay& s, double t0, std::uint32_t& node, LeafFn& leaf_fn,
                    std::uint64_t& visited) {
    bool near = false;
    node = descend<Count>(tree.nodes.data(), s, 0, t0, point_window(s, t0), near, visited);
    if (near && visit_point<Count>(tree.nodes.data(), s, t0, leaf_fn, visited)) return RopeStep::stop;
    return RopeStep::leaf;
}

/// After the leaf at `node` (at distance t) has been tested: moves `node` and t to the next leaf
/// along the ray, testing the leaves around an edge or corner passed near (visit_point). `touched`
/// gets bit k when this leaf has a face (not on the scene box) in the plane of a flat axis k, i.e.
/// leaves on the other side of that plane touch the ray too.
template <bool AnyHit, bool Count, class LeafFn>
RopeStep rope_next(const KdTree& tree, const RopeRay& s, double& t, std::uint32_t& node, const float& best_t,
                   LeafFn& leaf_fn, unsigned& touched, std::uint64_t& visited) {
    const KdNode* nodes = tree.nodes.data();
    const KdLeaf& leaf = tree.leaves[nodes[node].index()];
    double t_exit = INFINITY, t_far[3] = {0, 0, 0};
    int axis = -1;
    for (int k = 0; k < 3; ++k) {
        if (s.flat[k]) {
            const bool on_lo = s.o[k] == leaf.box.lo[k] && leaf.box.lo[k] != tree.box.lo[k];
            const bool on_hi = s.o[k] == leaf.box.hi[k] && leaf.box.hi[k] != tree.box.hi[k];
            if (on_lo || on_hi) touched |= 1u << k;
            continue;
        }
        t_far[k] = cross_t(s, k, s.up[k] ? leaf.box.hi[k] : leaf.box.lo[k]);
        if (t_far[k] < t_exit) t_exit = t_far[k], axis = k;
    }
    if (axis < 0) return RopeStep::end;
    // Nothing further on can be closer, or tie with it: a triangle hit exactly (or within the
    // crossing's rounding) at the exit may lie only in the next leaf, and the tie rule wants the
    // lowest prim among equal t, so the walk ends only when the best hit is clearly before the exit.
    if (!AnyHit && double(best_t) < t_exit && !near_plane(s, axis, t_exit, double(best_t))) return RopeStep::end;
    if (t_exit > s.t_end + s.tol[axis] * std::fabs(s.t_end)) return RopeStep::end;
    // Leaving near an edge or corner of this leaf (or exactly through one)? A face outside the
    // point window of the exit is neither within the tolerance of it nor crossed at t_exit
    // (point_window); only faces inside it are checked with their double crossings.
    const PointWindow w = point_window(s, t_exit);
    bool corner = false, near_exit = false;
    for (int k = 0; k < 3; ++k) {
        if (s.flat[k]) continue;
        const float far_face = s.up[k] ? leaf.box.hi[k] : leaf.box.lo[k];
        const float near_face = s.up[k] ? leaf.box.lo[k] : leaf.box.hi[k];
        if (k != axis && !(far_face < w.lo[k] || far_face > w.hi[k])) {
            corner |= t_far[k] == t_exit;
            near_exit |= near_plane(s, k, t_far[k], t_exit);
        }
        if (!(near_face < w.lo[k] || near_face > w.hi[k])) near_exit |= near_plane(s, k, cross_t(s, k, near_face), t_exit);
    }
    t = t_exit;
    const std::uint32_t rope = leaf.rope[kd_face(axis, s.up[axis])];
    // visit_point leaves out this leaf: it has just been tested with the same ray.
    const std::uint32_t tested = nodes[node].index();
    // Leaving the scene box near a face, but with the exit point clear of every split that bounds
    // this leaf (window_inside_leaf), visit_point would find this leaf alone: every random ray on
    // a flat model (its origin in the model's plane, the scene box flat, the exit at t = 0).
    if (rope == kd_no_rope)
        return near_exit && !window_inside_leaf(leaf, w) && visit_point<Count>(nodes, s, t, leaf_fn, visited, tested)
                   ? RopeStep::stop
                   : RopeStep::end;
    // Leaving exactly through an edge or corner, the next leaf is not across the exit face.
    node = descend<Count>(nodes, s, corner ? 0u : rope, t, w, near_exit, visited);
    if (near_exit && visit_point<Count>(nodes, s, t, leaf_fn, visited, tested)) return RopeStep::stop;
    return RopeStep::leaf;
}

/// Every step moves t forward (see the header comment); this bound on the leaves of one pass is
/// only a safety net.
inline std::size_t rope_max_steps(const KdTree& tree) { return 2 * tree.leaves.size() + 64; }

/// One walk from distance t0 with the current tie sides. Returns true when leaf_fn stopped it.
/// `touched`: see rope_next.
template <bool AnyHit, bool Count, class LeafFn>
bool walk_pass(const KdTree& tree, const RopeRay& s, double t0, const float& best_t, LeafFn& leaf_fn,
               unsigned& touched, std::uint64_t& visited) {
    double t = t0;
    std::uint32_t node = 0;
    RopeStep st = rope_first<Count>(tree, s, t0, node, leaf_fn, visited);
    const std::size_t max_steps = rope_max_steps(tree);
    for (std::size_t step = 0; step < max_steps; ++step) {
        if (st != RopeStep::leaf) return st == RopeStep::stop;
        if (leaf_fn(tree.nodes[node].index())) return true;
        st = rope_next<AnyHit, Count>(tree, s, t, node, best_t, leaf_fn, touched, visited);
    }
    return false;
}

/// How the walk of a ray begins (rope_start).
enum class RopeStart { none, walk, point };  ///< nothing to visit; walk from t0; only visit_point at t0

/// The per-ray constants of ray `r` (traceable) and its entry distance t0 into the scene box.
/// RopeStart::point: the ray passes by the scene box, but within the point tolerance of it (exactly
/// through an edge or corner of the box, up to the double rounding of the entry and exit, or a hair
/// outside), where the sheared triangle test may still hit: the leaves at t0 are to be tested
/// (visit_point; found by arbor's fuzzer).
inline RopeStart rope_start(const KdTree& tree, const Ray& r, RopeRay& s, double& t0_out) {
    double t0 = r.tnear, t1 = r.tfar;  // in registers, not through t0_out (a store per axis)
    t0_out = t0;
    const Vec3f dir = walk_direction(r.dir);
    const double dmax = std::max({std::fabs(double(dir.x)), std::fabs(double(dir.y)), std::fabs(double(dir.z))});
    s.dmax = dmax;
    for (int k = 0; k < 3; ++k) {
        s.o[k] = r.org[k];
        s.d[k] = dir[k];
        s.flat[k] = dir[k] == 0.0f;
        s.up[k] = !std::signbit(dir[k]);
        s.tie_right[k] = s.up[k];
        s.rcp[k] = 1.0 / double(dir[k]);
        s.tol[k] = point_tolerance * dmax * std::fabs(s.rcp[k]);
        const float lo = tree.box.lo[k], hi = tree.box.hi[k];
        if (s.flat[k]) {
            if (!flat_axis_can_hit(r.org[k], lo, hi)) return RopeStart::none;
            continue;
        }
        // Entry and exit by min and max, not by a branch on the sign of d (a coin toss per ray for
        // the predictor: diffuse rays leaving the alligator and woody, most of which miss the box,
        // ran 1.5x faster without it): the crossings are finite and the rounding is monotone, so
        // a <= b exactly when d > 0.
        const double a = cross_t(s, k, lo), b = cross_t(s, k, hi);
        t0 = std::max(t0, std::min(a, b));
        t1 = std::min(t1, std::max(a, b));
    }
    s.t_end = t1;
    t0_out = t0;
    if (t0 <= t1) return RopeStart::walk;
    double tol = 0.0;
    for (int k = 0; k < 3; ++k)
        if (!s.flat[k]) tol = std::max(tol, s.tol[k]);
    return t0 - t1 <= tol * std::max(std::fabs(t0), std::fabs(t1)) ? RopeStart::point : RopeStart::none;
}

/// The walks after a first pass that found the ray lying in leaf faces of flat axes (`touched`):
/// one more pass per other combination of tie sides of the flat axes. Returns true when leaf_fn
/// stopped the walk.
template <bool AnyHit, bool Count, class LeafFn>
bool walk_other_sides(const KdTree& tree, const RopeRay& s, double t0, const float& best_t, LeafFn& leaf_fn,
                      std::uint64_t& visited) {
    int flat_axes[3], nf = 0;
    for (int k = 0; k < 3; ++k)
        if (s.flat[k]) flat_axes[nf++] = k;
    for (unsigned combo = 1; combo < (1u << nf); ++combo) {
        RopeRay other = s;
        for (int i = 0; i < nf; ++i)
            if (combo & (1u << i)) other.tie_right[flat_axes[i]] = !s.tie_right[flat_axes[i]];
        unsigned unused = 0;
        if (walk_pass<AnyHit, Count>(tree, other, t0, best_t, leaf_fn, unused, visited)) return true;
    }
    return false;
}

/// walk_ropes after its start: `start` and the per-ray constants `s` and t0 from rope_start.
template <bool AnyHit, bool Count = false, class LeafFn>
void walk_ropes_from(const KdTree& tree, const RopeRay& s, double t0, RopeStart start, const float& best_t, LeafFn&& leaf_fn,
                     std::uint64_t& visited) {
    switch (start) {
    case RopeStart::none: return;
    case RopeStart::point: visit_point<Count>(tree.nodes.data(), s, t0, leaf_fn, visited); return;
    case RopeStart::walk: break;
    }
    unsigned touched = 0;
    if (walk_pass<AnyHit, Count>(tree, s, t0, best_t, leaf_fn, touched, visited) || touched == 0) return;
    // The ray lies in a leaf face plane of a flat axis: walk the other sides too.
    walk_other_sides<AnyHit, Count>(tree, s, t0, best_t, leaf_fn, visited);
}

/// Walks the leaves ray `r` passes, in order, calling leaf_fn(leaf index) -> bool (true: stop, for
/// any hit). For closest hit, `best_t` is the distance of the best hit so far (+inf while none),
/// updated by leaf_fn; the walk ends after the leaf whose exit is not before it. Untraceable rays
/// (ray_is_traceable) and an empty tree visit nothing. Leaves may be visited more than once.
/// Count: adds the interior nodes whose split plane the walk tested to `visited`.
template <bool AnyHit, bool Count = false, class LeafFn>
void walk_ropes(const KdTree& tree, const Ray& r, const float& best_t, LeafFn&& leaf_fn, std::uint64_t& visited) {
    if (tree.empty() || !ray_is_traceable(r)) return;
    RopeRay s;
    double t0 = 0.0;
    const RopeStart start = rope_start(tree, r, s, t0);
    walk_ropes_from<AnyHit, Count>(tree, s, t0, start, best_t, leaf_fn, visited);
}

}  // namespace arbor::accel::kd
