#include "accel/bvh/prim_refs.h"

#include "accel/util/prefault.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace arbor::accel {

namespace {

/// Triangles per block: large enough to amortize a task (~100k cycles), small enough to balance.
constexpr std::size_t block_size = 8192;

struct BlockResult {
    std::size_t count = 0;  ///< finite triangles in the block (pass 1), then the output offset
    Bounds bounds, centroid_bounds;
};

/// The nine corner coordinates of triangle t.
struct Corners {
    float x[3], y[3], z[3];
    Corners(const TriangleView& v, std::size_t t) {
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t i = v.indices[3 * t + k];
            x[k] = v.x[i], y[k] = v.y[i], z[k] = v.z[i];
        }
    }
    /// Same verdict as TriangleView::triangle_is_finite: v - v is 0 exactly when v is finite.
    bool finite() const {
        float s = 0.0f;
        for (int k = 0; k < 3; ++k) s += (x[k] - x[k]) + (y[k] - y[k]) + (z[k] - z[k]);
        return s == 0.0f;
    }
};

}  // namespace

PrimRefs make_prim_refs(const TriangleView& tris) {
    PrimRefs refs;
    const std::size_t n = tris.triangle_count();
    refs.triangles = n;
    const std::size_t blocks = (n + block_size - 1) / block_size;
    std::vector<BlockResult> block(blocks);

    // Pass 1: count the finite triangles of each block.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t b = r.begin(); b != r.end(); ++b) {
            const std::size_t end = std::min(n, (b + 1) * block_size);
            std::size_t count = 0;
            for (std::size_t t = b * block_size; t < end; ++t) count += Corners(tris, t).finite();
            block[b].count = count;
        }
    });
    // Exclusive prefix sum: each block's first output slot.
    std::size_t total = 0;
    for (BlockResult& b : block) {
        const std::size_t c = b.count;
        b.count = total;
        total += c;
    }
    refs.dropped_nonfinite = n - total;
    for (auto* v : {&refs.lo_x, &refs.lo_y, &refs.lo_z, &refs.hi_x, &refs.hi_y, &refs.hi_z, &refs.cx, &refs.cy, &refs.cz})
        resize_prefaulted(*v, total);
    resize_prefaulted(refs.prim_ids, total);

    // Pass 2: write boxes, centroids and ids at the block's offset; bounds per block.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t b = r.begin(); b != r.end(); ++b) {
            const std::size_t end = std::min(n, (b + 1) * block_size);
            std::size_t out = block[b].count;
            Bounds bounds, centroid_bounds;
            for (std::size_t t = b * block_size; t < end; ++t) {
                const Corners v(tris, t);
                if (!v.finite()) continue;
                const Bounds box{{std::min({v.x[0], v.x[1], v.x[2]}), std::min({v.y[0], v.y[1], v.y[2]}), std::min({v.z[0], v.z[1], v.z[2]})},
                                 {std::max({v.x[0], v.x[1], v.x[2]}), std::max({v.y[0], v.y[1], v.y[2]}), std::max({v.z[0], v.z[1], v.z[2]})}};
                const Vec3f c = box.lo * 0.5f + box.hi * 0.5f;
                refs.lo_x[out] = box.lo.x, refs.lo_y[out] = box.lo.y, refs.lo_z[out] = box.lo.z;
                refs.hi_x[out] = box.hi.x, refs.hi_y[out] = box.hi.y, refs.hi_z[out] = box.hi.z;
                refs.cx[out] = c.x, refs.cy[out] = c.y, refs.cz[out] = c.z;
                refs.prim_ids[out] = std::uint32_t(t);
                bounds.grow(box);
                centroid_bounds.grow(c);
                ++out;
            }
            block[b].bounds = bounds;
            block[b].centroid_bounds = centroid_bounds;
        }
    });
    for (const BlockResult& b : block) {
        refs.bounds.grow(b.bounds);
        refs.centroid_bounds.grow(b.centroid_bounds);
    }
    return refs;
}

}  // namespace arbor::accel
