#pragma once
/// The hierarchical winding number on any BVH layout (Barill et al. 2018, first order): a dipole per
/// child box, made bottom-up once (make_dipoles), and one walk per point (winding_at) that takes a
/// child's dipole when the point is farther than beta times its radius from its centroid, opens
/// it otherwise, and sums a leaf's triangles exactly. Both are templates over a small adapter, so
/// the scalar two-box layout (bvh/bvh2_winding.h) and the N-wide layouts (wide/wide_winding.h)
/// share this one implementation. An adapter `L` provides:
///
///   static constexpr std::size_t width;            // child slots per node
///   std::size_t nodes() const;                     // interior nodes, children after parents
///   bool root_is_leaf() const;                     // a tiny tree: the root is one leaf ...
///   Slots root_slots() const;                      // ... of these triangle slots
///   std::size_t children(std::uint32_t n) const;   // used slots of node n (0 .. width)
///   bool is_leaf(std::uint32_t n, std::size_t c) const;
///   std::uint32_t node(std::uint32_t n, std::size_t c) const;   // interior child's node
///   Slots slots(std::uint32_t n, std::size_t c) const;          // leaf child's triangle slots
///   Bounds box(std::uint32_t n, std::size_t c) const;
///   Vec3f vertex(std::uint32_t slot, int k) const;
#include "accel/core/solid_angle.h"

#include "simd/simd.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <numbers>
#include <span>
#include <vector>

namespace arbor::accel {

/// A leaf's triangles: slots first .. first + count - 1.
struct Slots {
    std::uint32_t first = 0, count = 0;
};

namespace detail {

/// The dipole of triangle slots `s`; radius: the farthest corner from the centroid (exact, in double).
template <class L>
Dipole leaf_dipole(const L& t, Slots s) {
    Dipole d;
    Vec3d weighted{0.0, 0.0, 0.0}, plain{0.0, 0.0, 0.0};
    for (std::uint32_t i = s.first; i < s.first + s.count; ++i) {
        const Vec3d a = to_double(t.vertex(i, 0)), b = to_double(t.vertex(i, 1)), c = to_double(t.vertex(i, 2));
        const Vec3d n = simd::cross(b - a, c - a) * 0.5;
        const double area = simd::length(n);
        const Vec3d g = (a + b + c) * (1.0 / 3.0);
        d.normal += n;
        d.area += area;
        weighted += g * area;
        plain += g;
    }
    // Zero area (degenerate triangles only): the plain mean, so the center stays among them.
    d.center = d.area > 0.0 ? weighted * (1.0 / d.area) : plain * (1.0 / double(std::max<std::uint32_t>(s.count, 1)));
    for (std::uint32_t i = s.first; i < s.first + s.count; ++i)
        for (int k = 0; k < 3; ++k) d.radius = std::max(d.radius, simd::length(to_double(t.vertex(i, k)) - d.center));
    return d;
}

/// The farthest corner of `box` from p: a radius about p that holds everything in the box.
inline double box_reach(const Bounds& box, const Vec3d& p) {
    double s = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double lo = std::fabs(double(box.lo[k]) - p[k]), hi = std::fabs(double(box.hi[k]) - p[k]);
        const double m = std::max(lo, hi);
        s += m * m;
    }
    return std::sqrt(s);
}

/// The dipole of children `parts` of one node (box: the node's child box holding them all).
inline Dipole merge_dipoles(std::span<const Dipole> parts, const Bounds& box) {
    Dipole d;
    Vec3d weighted{0.0, 0.0, 0.0}, plain{0.0, 0.0, 0.0};
    for (const Dipole& p : parts) {
        d.normal += p.normal;
        d.area += p.area;
        weighted += p.center * p.area;
        plain += p.center;
    }
    d.center =
        d.area > 0.0 ? weighted * (1.0 / d.area) : plain * (1.0 / double(std::max<std::size_t>(parts.size(), 1)));
    // Two bounds on the distance from the new center to any triangle point, the smaller kept: the
    // children's spheres about the new center, and the box's farthest corner.
    double r = 0.0;
    for (const Dipole& p : parts) r = std::max(r, simd::length(p.center - d.center) + p.radius);
    d.radius = std::min(r, box_reach(box, d.center));
    return d;
}

}  // namespace detail

/// The dipoles of one node's child slots in SoA form, each array padded to whole double batches
/// so that the walk tests and sums them a batch at a time (unused slots: zeros, masked out by the
/// walk). Per slot: the center, the area vector, the radius and the unsigned area (Dipole).
template <std::size_t W>
struct alignas(64) DipoleSlots {
    using Batch = xsimd::batch<double>;
    static constexpr std::size_t lanes = Batch::size;
    static constexpr std::size_t size = (W + lanes - 1) / lanes * lanes;
    double cx[size], cy[size], cz[size];
    double nx[size], ny[size], nz[size];
    double radius[size], area[size];

    void set(std::size_t c, const Dipole& d) {
        cx[c] = d.center.x, cy[c] = d.center.y, cz[c] = d.center.z;
        nx[c] = d.normal.x, ny[c] = d.normal.y, nz[c] = d.normal.z;
        radius[c] = d.radius, area[c] = d.area;
    }
};

namespace detail {

/// The farthest triangle corner under interior node `m` from `center` (every leaf below m
/// visited; `todo` is scratch).
template <class L>
double farthest_corner(const L& t, std::uint32_t m, const Vec3d& center, std::vector<std::uint32_t>& todo) {
    double r2 = 0.0;
    todo.assign(1, m);
    while (!todo.empty()) {
        const std::uint32_t k = todo.back();
        todo.pop_back();
        for (std::size_t c = 0; c < t.children(k); ++c) {
            if (!t.is_leaf(k, c)) {
                todo.push_back(t.node(k, c));
                continue;
            }
            const Slots s = t.slots(k, c);
            for (std::uint32_t i = s.first; i < s.first + s.count; ++i)
                for (int v = 0; v < 3; ++v) {
                    const Vec3d e = to_double(t.vertex(i, v)) - center;
                    r2 = std::max(r2, simd::dot(e, e));
                }
        }
    }
    return std::sqrt(r2);
}

}  // namespace detail

/// One DipoleSlots per interior node, dipoles[n] for node n (child slot c: lane c). Leaves in
/// parallel, then the interior bottom-up; the result does not depend on the number of threads.
template <class L>
std::vector<DipoleSlots<L::width>> make_dipoles(const L& t) {
    constexpr std::size_t w = L::width;
    std::vector<Dipole> dip(t.nodes() * w);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, t.nodes(), 64), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t n = r.begin(); n != r.end(); ++n)
            for (std::size_t c = 0; c < t.children(std::uint32_t(n)); ++c)
                if (t.is_leaf(std::uint32_t(n), c))
                    dip[n * w + c] = detail::leaf_dipole(t, t.slots(std::uint32_t(n), c));
    });
    // Children come after their parents, so walking backwards meets every child node first.
    for (std::size_t n = t.nodes(); n-- > 0;)
        for (std::size_t c = 0; c < t.children(std::uint32_t(n)); ++c)
            if (!t.is_leaf(std::uint32_t(n), c)) {
                const std::uint32_t m = t.node(std::uint32_t(n), c);
                dip[n * w + c] =
                    detail::merge_dipoles({dip.data() + std::size_t(m) * w, t.children(m)}, t.box(std::uint32_t(n), c));
            }
    // An interior child's radius so far is a bound from its children (merge_dipoles); its exact
    // value, the farthest triangle corner under it from its center, is smaller and lets more points
    // take the dipole at the same beta (the bound stays a bound: a triangle lies in its corners'
    // hull). Each child's leaves are visited once per level above them; the maximum does not
    // depend on the order, so neither on the threads. Wide layouts only: on them the measured
    // error stays at or below libigl's at the same beta; on the deep binary layout it rose above
    // it (spot, 150 points: max 0.048 -> 0.063, libigl 0.033; docs/robustness.md).
    if constexpr (w > 2)
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, t.nodes(), 16),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              std::vector<std::uint32_t> todo;
                              for (std::size_t n = r.begin(); n != r.end(); ++n)
                                  for (std::size_t c = 0; c < t.children(std::uint32_t(n)); ++c) {
                                      if (t.is_leaf(std::uint32_t(n), c)) continue;
                                      Dipole& d = dip[n * w + c];
                                      const std::uint32_t m = t.node(std::uint32_t(n), c);
                                      d.radius = std::min(d.radius, detail::farthest_corner(t, m, d.center, todo));
                                  }
                          });
    std::vector<DipoleSlots<w>> soa(t.nodes(), DipoleSlots<w>{});
    for (std::size_t n = 0; n < t.nodes(); ++n)
        for (std::size_t c = 0; c < t.children(std::uint32_t(n)); ++c) soa[n].set(c, dip[n * w + c]);
    return soa;
}

namespace detail {

/// 1 / (r2 sqrt(r2)) for r2 > 0, lane by lane: with AVX-512, the 14-bit reciprocal square root
/// refined by two Newton steps (relative error about 2^-50, far below the dipole's own), which
/// costs a fraction of the square root and the division it replaces; else those two.
template <class B>
B inv_length_cubed(const B& r2) {
#if XSIMD_WITH_AVX512F
    if constexpr (std::is_same_v<typename B::value_type, double> && B::size == 8) {
        B y(_mm512_rsqrt14_pd(r2));
        const B half = r2 * B(0.5);
        const __m512d three_halves = _mm512_set1_pd(1.5);
        y = y * B(_mm512_fnmadd_pd(half, y * y, three_halves));  // xsimd 8.1 has no AVX-512 fnma
        y = y * B(_mm512_fnmadd_pd(half, y * y, three_halves));
        return y * y * y;
    }
#endif
    return B(1.0) / (r2 * xsimd::sqrt(r2));
}

/// The sum of the exact winding numbers of a leaf's triangles around p: the adapter's own batch
/// evaluation when it has one (L::leaf_winding), else triangle by triangle.
template <class L>
double leaf_winding(const L& t, Slots s, const Vec3f& p) {
    if constexpr (requires { t.leaf_winding(s, p); }) {
        return t.leaf_winding(s, p);
    } else {
        double sum = 0.0;
        for (std::uint32_t i = s.first; i < s.first + s.count; ++i)
            sum += triangle_winding(p, t.vertex(i, 0), t.vertex(i, 1), t.vertex(i, 2));
        return sum;
    }
}

}  // namespace detail

/// The winding number of the tree's triangles around p (finite): dipoles for the children farther
/// than beta * radius (compared squared: |center - p|^2 > beta^2 radius^2), exact solid angles in
/// the leaves opened. A node's children are tested and their dipoles summed a double batch at a
/// time, into per-lane sums added up once at the end. With Bound, `bound` gets the sum of the error
/// bounds of the dipoles used. `stack` is scratch (kept between calls to reuse its memory).
template <bool Bound, class L>
double winding_at(const L& t, std::span<const DipoleSlots<L::width>> dip, const Vec3f& p, double beta, double& bound,
                  std::vector<std::uint32_t>& stack) {
    static_assert(L::width <= 32, "a node's near children are bits of a 32-bit mask");
    using Slots_ = DipoleSlots<L::width>;
    using B = typename Slots_::Batch;
    constexpr std::size_t lanes = Slots_::lanes;
    bound = 0.0;
    if (t.root_is_leaf()) return detail::leaf_winding(t, t.root_slots(), p);
    if (t.nodes() == 0) return 0.0;
    const B qx(double(p.x)), qy(double(p.y)), qz(double(p.z)), beta2(beta * beta);
    // Lane numbers, to mask the slots past a node's children.
    alignas(64) double lane_ids[lanes];
    for (std::size_t i = 0; i < lanes; ++i) lane_ids[i] = double(i);
    const B ids = B::load_aligned(lane_ids);
    B far_sum(0.0), bound_sum(0.0);
    double near_sum = 0.0;
    stack.clear();
    stack.push_back(0);
    while (!stack.empty()) {
        const std::uint32_t n = stack.back();
        stack.pop_back();
        const Slots_& d = dip[n];
        const std::size_t kids = t.children(n);
        // All the node's dipoles first, into one sum added to far_sum once (far_sum lives in
        // memory across the leaf calls below: one round trip per node, not per batch) ...
        B node_far(0.0), node_bound(0.0);
        std::uint32_t near_bits = 0;  // bit c: child c is near
        for (std::size_t g = 0; g < kids; g += lanes) {
            const B rx = B::load_aligned(d.cx + g) - qx, ry = B::load_aligned(d.cy + g) - qy,
                    rz = B::load_aligned(d.cz + g) - qz;
            const B r2 = rx * rx + ry * ry + rz * rz;
            const B rad = B::load_aligned(d.radius + g);
            const auto used = ids < B(double(kids - g));
            const auto far = used && r2 > beta2 * (rad * rad);
            if (xsimd::any(far)) {
                const B dot = B::load_aligned(d.nx + g) * rx + B::load_aligned(d.ny + g) * ry + B::load_aligned(d.nz + g) * rz;
                node_far += xsimd::select(far, dot * detail::inv_length_cubed(r2), B(0.0));
                if constexpr (Bound) {
                    const B gap = xsimd::sqrt(r2) - rad;
                    node_bound += xsimd::select(far, B::load_aligned(d.area + g) * rad / (gap * gap * gap), B(0.0));
                }
            }
            near_bits |= simd::to_bits(used && !far) << g;
        }
        far_sum += node_far;
        if constexpr (Bound) bound_sum += node_bound;
        // ... then the near children, in slot order: leaves summed exactly, nodes opened.
        for (; near_bits != 0; near_bits &= near_bits - 1) {
            const std::size_t c = std::size_t(std::countr_zero(near_bits));
            if (t.is_leaf(n, c))
                near_sum += detail::leaf_winding(t, t.slots(n, c), p);
            else
                stack.push_back(t.node(n, c));
        }
    }
    if constexpr (Bound) bound = xsimd::hadd(bound_sum) / (2.0 * std::numbers::pi);
    return near_sum + xsimd::hadd(far_sum) / (4.0 * std::numbers::pi);
}

/// winding_at over a batch (WindingTree::winding_numbers): NaN for non-finite points.
template <class L>
void winding_batch(const L& t, std::span<const DipoleSlots<L::width>> dip, std::span<const Vec3f> points, double beta,
                   std::span<double> out, std::span<double> bound) {
    std::vector<std::uint32_t> stack;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Vec3f& p = points[i];
        double b = 0.0;
        const bool finite = std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
        if (!finite) out[i] = std::numeric_limits<double>::quiet_NaN();
        else if (bound.empty()) out[i] = winding_at<false>(t, dip, p, beta, b, stack);
        else out[i] = winding_at<true>(t, dip, p, beta, b, stack);
        if (!bound.empty()) bound[i] = finite ? b : std::numeric_limits<double>::quiet_NaN();
    }
}

}  // namespace arbor::accel
