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

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
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

/// One dipole per child slot, dipoles[n * L::width + c] for child c of node n (unused slots: zero
/// dipoles). Leaves in parallel, then the interior bottom-up; the result does not depend on the
/// number of threads.
template <class L>
std::vector<Dipole> make_dipoles(const L& t) {
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
    return dip;
}

/// The winding number of the tree's triangles around p (finite): dipoles for the children farther
/// than beta * radius, exact solid angles in the leaves opened. `bound` gets the sum of the error
/// bounds of the dipoles used. `stack` is scratch (kept between calls to reuse its memory).
template <class L>
double winding_at(const L& t, std::span<const Dipole> dip, const Vec3f& p, double beta, double& bound,
                  std::vector<std::uint32_t>& stack) {
    constexpr std::size_t w = L::width;
    const Vec3d q = to_double(p);
    double sum = 0.0;
    bound = 0.0;
    const auto leaf = [&](Slots s) {
        for (std::uint32_t i = s.first; i < s.first + s.count; ++i)
            sum += triangle_winding(p, t.vertex(i, 0), t.vertex(i, 1), t.vertex(i, 2));
    };
    if (t.root_is_leaf()) {
        leaf(t.root_slots());
        return sum;
    }
    if (t.nodes() == 0) return 0.0;
    stack.clear();
    stack.push_back(0);
    while (!stack.empty()) {
        const std::uint32_t n = stack.back();
        stack.pop_back();
        for (std::size_t c = 0; c < t.children(n); ++c) {
            const Dipole& d = dip[std::size_t(n) * w + c];
            const double dist = simd::length(d.center - q);
            if (dist > beta * d.radius) {
                sum += dipole_winding(d, q);
                bound += dipole_error_bound(d, dist);
            } else if (t.is_leaf(n, c)) {
                leaf(t.slots(n, c));
            } else {
                stack.push_back(t.node(n, c));
            }
        }
    }
    return sum;
}

/// winding_at over a batch (WindingTree::winding_numbers): NaN for non-finite points.
template <class L>
void winding_batch(const L& t, std::span<const Dipole> dip, std::span<const Vec3f> points, double beta,
                   std::span<double> out, std::span<double> bound) {
    std::vector<std::uint32_t> stack;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Vec3f& p = points[i];
        double b = 0.0;
        const bool finite = std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
        out[i] = finite ? winding_at(t, dip, p, beta, b, stack) : std::numeric_limits<double>::quiet_NaN();
        if (!bound.empty()) bound[i] = finite ? b : std::numeric_limits<double>::quiet_NaN();
    }
}

}  // namespace arbor::accel
