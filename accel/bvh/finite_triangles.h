#pragma once
/// for_finite_triangles(): the pass over the triangles that PrimRefs and BuildPrims share. Two
/// tbb::parallel_for passes over fixed blocks: the first counts the finite triangles of each block,
/// an exclusive prefix sum gives each block its first output slot, then `allocate(total)` runs once
/// and `write(slot, t, box, centroid)` once per finite triangle t, at its slot in triangle order.
/// The bounds are exact min/max, so everything is bit-identical for any thread count.
#include "accel/core/geometry.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace arbor::accel {

/// What the pass found: finite triangles, the union of their boxes and the bounds of their
/// centroids (empty when there are none).
struct FiniteTriangles {
    std::size_t finite = 0;
    Bounds bounds, centroid_bounds;
};

namespace finite_detail {

/// Triangles per block: large enough to amortize a task (~100k cycles), small enough to balance.
constexpr std::size_t block_size = 8192;

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
    Bounds box() const {
        return {{std::min({x[0], x[1], x[2]}), std::min({y[0], y[1], y[2]}), std::min({z[0], z[1], z[2]})},
                {std::max({x[0], x[1], x[2]}), std::max({y[0], y[1], y[2]}), std::max({z[0], z[1], z[2]})}};
    }
};

struct Block {
    std::size_t offset = 0;  ///< finite triangles in the block (pass 1), then its first slot
    Bounds bounds, centroid_bounds;
};

}  // namespace finite_detail

/// The centroid of a box as every builder computes it: lo/2 + hi/2 (finite even near FLT_MAX).
inline Vec3f box_centroid(const Bounds& b) { return b.lo * 0.5f + b.hi * 0.5f; }

template <class Allocate, class Write>
FiniteTriangles for_finite_triangles(const TriangleView& tris, Allocate&& allocate, Write&& write) {
    using namespace finite_detail;
    const std::size_t n = tris.triangle_count();
    const std::size_t blocks = (n + block_size - 1) / block_size;
    std::vector<Block> block(blocks);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t b = r.begin(); b != r.end(); ++b) {
            const std::size_t end = std::min(n, (b + 1) * block_size);
            std::size_t count = 0;
            for (std::size_t t = b * block_size; t < end; ++t) count += Corners(tris, t).finite();
            block[b].offset = count;
        }
    });
    FiniteTriangles out;
    for (Block& b : block) {  // exclusive prefix sum: each block's first output slot
        const std::size_t c = b.offset;
        b.offset = out.finite;
        out.finite += c;
    }
    allocate(out.finite);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t b = r.begin(); b != r.end(); ++b) {
            const std::size_t end = std::min(n, (b + 1) * block_size);
            std::size_t slot = block[b].offset;
            Bounds bounds, centroid_bounds;
            for (std::size_t t = b * block_size; t < end; ++t) {
                const Corners v(tris, t);
                if (!v.finite()) continue;
                const Bounds box = v.box();
                const Vec3f c = box_centroid(box);
                write(slot++, t, box, c);
                bounds.grow(box);
                centroid_bounds.grow(c);
            }
            block[b].bounds = bounds;
            block[b].centroid_bounds = centroid_bounds;
        }
    });
    for (const Block& b : block) {
        out.bounds.grow(b.bounds);
        out.centroid_bounds.grow(b.centroid_bounds);
    }
    return out;
}

}  // namespace arbor::accel
