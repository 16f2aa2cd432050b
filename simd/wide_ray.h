#pragma once
/// WideRay<T>: one ray broadcast to every lane of T, for testing it against lanes<T> boxes (a wide
/// node) or lanes<T> triangles (a leaf block) at once. Its constants are bit for bit those of the
/// scalar slab_ray() and woop_shear() (tested), so a wide test does per lane exactly what the
/// scalar test does on that box or triangle.
#include "simd/ray_box.h"
#include "simd/ray.h"
#include "simd/ray_triangle.h"

namespace arbor::simd {

template <class T> struct WideRay {
    Vec3<T> org;            ///< origin in x, y, z order
    Vec3<T> org_perm;       ///< origin in the (kx, ky, kz) order of the triangle test
    Vec3<T> rcp_near;       ///< 1/d
    Vec3<T> rcp_far;        ///< 1/d padded by 2 ulps (Ize)
    T tnear, tfar;          ///< tfar may be lowered by the caller as hits are found
    T tbox;                 ///< box_tfar(tfar), what the box tests cull against (walk_wide keeps it)
    T sx, sy, sz;           ///< Woop shear
    int near_is_hi[3] = {}; ///< 1 when d[k] has its sign bit set: the near plane is the box's max
    int kx = 0, ky = 1, kz = 2;
    bool traceable = false; ///< false: tnear = +inf and tfar = -inf, no test accepts the ray
    /// Traceable and is_plain (ray_box.h: tnear >= 0, every reciprocal finite and normal): the box
    /// test may take the shorter form ray_boxes_plain (box_kernels.h).
    bool plain = false;
};

/// The ray o + t d, t in [tnear, tfar]. A ray that fails the traceable rule of simd/ray.h (NaN or
/// Inf components, zero direction, tnear > tfar) is kept as `traceable = false` and never hits.
template <class T> inline WideRay<T> wide_ray(const Vec3f& o, const Vec3f& d, float tnear, float tfar) {
    const bool ok = traceable<float>(o, d, tnear, tfar);
    // slab_ray()'s reciprocals, with the padding done by the batch slab_far (bit-identical, and
    // ~20 ns per ray cheaper than six std::nextafter calls).
    // (Built in registers: a 16-byte load of three just-stored floats would stall store forwarding.)
    const float dmax = std::max(std::fabs(d.x), std::max(std::fabs(d.y), std::fabs(d.z)));
    const Float4 rcp4 = slab_rcp(Float4(_mm_setr_ps(d.x, d.y, d.z, dmax)), Float4(dmax)), pad4 = slab_far(rcp4);
    alignas(16) float rn[4], rf[4];
    rcp4.store_aligned(rn);
    pad4.store_aligned(rf);
    SlabRay s;
    for (int k = 0; k < 3; ++k) {
        s.rcp_near[k] = rn[k];
        s.rcp_far[k] = rf[k];
        s.near_is_hi[k] = std::signbit(d[k]) ? 1 : 0;
    }
    const WoopShear w = woop_shear(d);
    WideRay<T> r;
    r.traceable = ok;
    r.org = {T(o.x), T(o.y), T(o.z)};
    r.org_perm = {T(o[w.kx]), T(o[w.ky]), T(o[w.kz])};
    r.rcp_near = {T(s.rcp_near.x), T(s.rcp_near.y), T(s.rcp_near.z)};
    r.rcp_far = {T(s.rcp_far.x), T(s.rcp_far.y), T(s.rcp_far.z)};
    r.tnear = T(ok ? tnear : INFINITY);
    r.tfar = T(ok ? tfar : -INFINITY);
    r.tbox = T(box_tfar(ok ? tfar : -INFINITY));
    r.sx = T(w.sx);
    r.sy = T(w.sy);
    r.sz = T(w.sz);
    for (int k = 0; k < 3; ++k) r.near_is_hi[k] = s.near_is_hi[k];
    r.plain = ok && is_plain(tnear, s.rcp_near, s.rcp_far);
    r.kx = w.kx;
    r.ky = w.ky;
    r.kz = w.kz;
    return r;
}

}  // namespace arbor::simd
