#include "accel/bvh/build_prims.h"

#include "accel/bvh/finite_triangles.h"
#include "accel/util/prefault.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace arbor::accel {

BuildPrims make_build_prims(const TriangleView& tris) {
    BuildPrims out;
    out.triangles = tris.triangle_count();
    const FiniteTriangles f = for_finite_triangles(
        tris, [&](std::size_t total) { resize_prefaulted(out.prims, total); },  // every element written below
        [&](std::size_t slot, std::size_t t, const Bounds& box, const Vec3f&) {
            out.prims[slot] = {{box.lo.x, box.lo.y, box.lo.z}, std::uint32_t(t), {box.hi.x, box.hi.y, box.hi.z}, 0};
        });
    out.dropped_nonfinite = out.triangles - f.finite;
    out.bounds = f.bounds;
    out.centroid_bounds = f.centroid_bounds;
    return out;
}

BuildPrims make_build_prims(const PrimRefs& refs) {
    BuildPrims out;
    out.triangles = refs.triangles;
    out.dropped_nonfinite = refs.dropped_nonfinite;
    out.bounds = refs.bounds;
    out.centroid_bounds = refs.centroid_bounds;
    resize_prefaulted(out.prims, refs.size());  // every element written below: no zeroing pass
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, refs.size(), 16384), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i)
            out.prims[i] = {{refs.lo_x[i], refs.lo_y[i], refs.lo_z[i]}, refs.prim_ids[i],
                            {refs.hi_x[i], refs.hi_y[i], refs.hi_z[i]}, 0};
    });
    return out;
}

}  // namespace arbor::accel
