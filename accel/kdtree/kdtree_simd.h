#pragma once
/// KdSimdPaths: the SIMD traversal paths of the kd-tree (TracePath::single and TracePath::packet)
/// over its rope walk (kdtree_traverse.h) and its leaves' triangles in SIMD blocks
/// (kdtree_blocks.h). KdTreeAccel owns one; the block width and packet width are static inside.
/// Both paths visit, for every ray, exactly the leaves the scalar walk visits, in the same order,
/// and keep the scalar path's hit rule (closest: the smallest t, on equal t the lowest prim; any
/// hit: the first hit in walk order), so their answers are bit-identical to the scalar path's.
#include "accel/accel.h"
#include "accel/kdtree/kdtree_node.h"

#include <memory>
#include <span>

namespace arbor::accel {

class KdSimdPaths {
public:
    virtual ~KdSimdPaths() = default;
    /// Triangles per SIMD block (8 or 16).
    virtual std::size_t block_width() const = 0;
    /// Rays per packet of the packet path (8 or 16).
    virtual std::size_t packet_lanes() const = 0;
    /// Bytes of the triangle blocks.
    virtual std::size_t memory_bytes() const = 0;
    /// Closest hit (any_hit = false) or any hit per ray through `tree` (the one the paths were
    /// made from), by `path` (packet; anything else is traced as single). Single-threaded; call
    /// from many threads on disjoint spans. Untraceable rays (ray_is_traceable) miss.
    virtual void trace(const KdTree& tree, std::span<const Ray> rays, std::span<Hit> hits, TracePath path,
                       bool any_hit) const = 0;
};

/// Block width when none is asked for (perf/results/kdtree-simd-*.md).
std::uint32_t default_kd_block_width();

/// The SIMD paths of `tree`: blocks of cfg.kd_block_width triangles (0 or unsupported: the
/// default), packets of cfg.packet_lanes rays (0: 16 with AVX-512, else 8), leaves reached by at
/// most cfg.packet_switch lanes of a packet (-1: lanes / 8) tested one lane at a time.
std::unique_ptr<KdSimdPaths> make_kd_simd_paths(const KdTree& tree, const BuildConfig& cfg);

}  // namespace arbor::accel
