#include "accel/prim_refs.h"

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
            for (std::size_t t = b * block_size; t < end; ++t) count += tris.triangle_is_finite(t);
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
        v->resize(total);
    refs.prim_ids.resize(total);

    // Pass 2: write boxes, centroids and ids at the block's offset; bounds per block.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t b = r.begin(); b != r.end(); ++b) {
            const std::size_t end = std::min(n, (b + 1) * block_size);
            std::size_t out = block[b].count;
            Bounds bounds, centroid_bounds;
            for (std::size_t t = b * block_size; t < end; ++t) {
                if (!tris.triangle_is_finite(t)) continue;
                const Bounds box = tris.triangle_bounds(t);
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
