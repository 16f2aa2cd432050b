#include "accel/bvh/prim_refs.h"

#include "accel/bvh/finite_triangles.h"
#include "accel/util/prefault.h"

namespace arbor::accel {

PrimRefs make_prim_refs(const TriangleView& tris) {
    PrimRefs refs;
    refs.triangles = tris.triangle_count();
    const FiniteTriangles f = for_finite_triangles(
        tris,
        [&](std::size_t total) {
            for (auto* v : {&refs.lo_x, &refs.lo_y, &refs.lo_z, &refs.hi_x, &refs.hi_y, &refs.hi_z, &refs.cx, &refs.cy, &refs.cz})
                resize_prefaulted(*v, total);
            resize_prefaulted(refs.prim_ids, total);
        },
        [&](std::size_t out, std::size_t t, const Bounds& box, const Vec3f& c) {
            refs.lo_x[out] = box.lo.x, refs.lo_y[out] = box.lo.y, refs.lo_z[out] = box.lo.z;
            refs.hi_x[out] = box.hi.x, refs.hi_y[out] = box.hi.y, refs.hi_z[out] = box.hi.z;
            refs.cx[out] = c.x, refs.cy[out] = c.y, refs.cz[out] = c.z;
            refs.prim_ids[out] = std::uint32_t(t);
        });
    refs.dropped_nonfinite = refs.triangles - f.finite;
    refs.bounds = f.bounds;
    refs.centroid_bounds = f.centroid_bounds;
    return refs;
}

}  // namespace arbor::accel
