#pragma once
/// Ray/box kernels over the lane type T, all built on the one slab_test template of ray_box.h:
///   - packet_box:  a RayPacket (lanes<T> rays) against one box, e.g. a node in packet traversal;
///   - ray_boxes:   one WideRay against lanes<T> boxes in SoA form, e.g. the children of a wide node.
/// Both return the lanes that hit and the entry distance per lane (valid where hit). Both cull
/// against the ray's tbox (box_tfar of its tfar, ray_box.h), not tfar itself.
#include "simd/ray_packet.h"
#include "simd/wide_ray.h"

#include <cstddef>

namespace arbor::simd {

/// lanes<T> boxes of a wide node in SoA form: b[0] holds the lower corners, b[1] the upper ones,
/// per axis and lane. Unused slots must be empty boxes, lo = +inf and hi = -inf: they never hit
/// (a NaN plane would be ignored by the slab test, which keeps it conservative, and so would hit).
template <std::size_t N> struct BoxesSoA {
    alignas(N * sizeof(float) >= 64 ? 64 : N * sizeof(float)) float b[2][3][N];

    void set(std::size_t i, const Vec3f& lo, const Vec3f& hi) {
        for (int k = 0; k < 3; ++k) {
            b[0][k][i] = lo[k];
            b[1][k][i] = hi[k];
        }
    }
    void set_empty(std::size_t i) { set(i, Vec3f(INFINITY), Vec3f(-INFINITY)); }
    /// Corners of box i.
    Vec3f lo(std::size_t i) const { return {b[0][0][i], b[0][1][i], b[0][2][i]}; }
    Vec3f hi(std::size_t i) const { return {b[1][0][i], b[1][1][i], b[1][2][i]}; }
};

/// A packet against one box [lo, hi]: the near plane of each axis is chosen per lane by the sign
/// bit of that lane's direction. Inactive lanes never hit.
namespace detail {
/// Each lane's near and far planes of box [lo, hi], by the sign bits of its direction.
template <class T>
ARBOR_INLINE void packet_planes(const RayPacket<T>& p, const Vec3f& lo, const Vec3f& hi, Vec3<T>& n, Vec3<T>& f) {
    for (int k = 0; k < 3; ++k) {
        const T l(lo[k]), h(hi[k]);
        n[k] = select(p.near_is_hi[k], h, l);
        f[k] = select(p.near_is_hi[k], l, h);
    }
}
}  // namespace detail

template <class T>
ARBOR_INLINE Mask<T> packet_box(const RayPacket<T>& p, const Vec3f& lo, const Vec3f& hi, T& t_entry) {
    Vec3<T> n, f;
    detail::packet_planes(p, lo, hi, n, f);
    return slab_test<T>(n, f, p.org, p.rcp_near, p.rcp_far, p.tnear, p.tbox, t_entry) & p.active;
}

/// The same for a packet with RayPacket::plain set, by slab_test_plain (ray_box.h: the same hits,
/// entry distances equal as numbers). Lanes outside p.active may compute anything; they are masked out.
/// (Both forced inline: as calls, one per child of each node the packet visits, they took 5.6% of
/// the packet path on shadow rays and reloaded the packet's constants at every call.)
template <class T>
ARBOR_INLINE Mask<T> packet_box_plain(const RayPacket<T>& p, const Vec3f& lo, const Vec3f& hi, T& t_entry) {
    Vec3<T> n, f;
    detail::packet_planes(p, lo, hi, n, f);
    return slab_test_plain<T>(n, f, p.org, p.rcp_near, p.rcp_far, p.tnear, p.tbox, t_entry) & p.active;
}

/// One ray against lanes<T> boxes already sorted into near and far planes.
template <class T>
inline Mask<T> ray_boxes_sorted(const WideRay<T>& r, const Vec3<T>& near_plane, const Vec3<T>& far_plane, T& t_entry) {
    return slab_test<T>(near_plane, far_plane, r.org, r.rcp_near, r.rcp_far, r.tnear, r.tbox, t_entry);
}

/// One ray against lanes<T> boxes stored as BoxesSoA<lanes<T>> (`soa` points at its b[0][0]): the
/// near and far planes are picked by the ray's sign bits, without a branch.
namespace detail {
/// The ray's near and far planes of the lanes<T> boxes at `soa`, picked by its sign bits.
template <class T> ARBOR_INLINE void node_planes(const WideRay<T>& r, const float* soa, Vec3<T>& near_plane, Vec3<T>& far_plane) {
    constexpr std::size_t n = lanes<T>;
    for (int k = 0; k < 3; ++k) {
        near_plane[k] = load_lanes<T>(soa + (std::size_t(r.near_is_hi[k]) * 3 + k) * n);
        far_plane[k] = load_lanes<T>(soa + (std::size_t(1 - r.near_is_hi[k]) * 3 + k) * n);
    }
}
}  // namespace detail

template <class T> ARBOR_INLINE Mask<T> ray_boxes(const WideRay<T>& r, const float* soa, T& t_entry) {
    Vec3<T> near_plane, far_plane;
    detail::node_planes(r, soa, near_plane, far_plane);
    return ray_boxes_sorted(r, near_plane, far_plane, t_entry);
}
/// The same test for a ray with WideRay::plain set, by slab_test_plain (ray_box.h: the same hits,
/// entry distances equal as numbers, in fewer dependent steps per node).
template <class T> ARBOR_INLINE Mask<T> ray_boxes_plain(const WideRay<T>& r, const float* soa, T& t_entry) {
    Vec3<T> near_plane, far_plane;
    detail::node_planes(r, soa, near_plane, far_plane);
    return slab_test_plain<T>(near_plane, far_plane, r.org, r.rcp_near, r.rcp_far, r.tnear, r.tbox, t_entry);
}

template <class T, std::size_t N> inline Mask<T> ray_boxes(const WideRay<T>& r, const BoxesSoA<N>& boxes, T& t_entry) {
    static_assert(N == lanes<T>, "one lane per box");
    return ray_boxes(r, &boxes.b[0][0][0], t_entry);
}

}  // namespace arbor::simd
