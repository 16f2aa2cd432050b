#pragma once
/// WidePaths: the SIMD traversal paths of a BVH (TracePath::single and TracePath::packet) over an
/// N-wide layout collapsed from its BinaryBvh (wide_layout.h). BvhAccel owns one next to its
/// scalar reference layout; one virtual call per batch, the width is static inside.
#include "accel/accel.h"
#include "accel/bvh/binary_bvh.h"
#include "accel/wide/wide_layout.h"

#include <memory>
#include <span>

namespace arbor::accel {

class WidePaths {
public:
    virtual ~WidePaths() = default;
    /// Children per node (4, 8 or 16).
    virtual std::size_t width() const = 0;
    /// Bytes of the nodes, triangle blocks and ids.
    virtual std::size_t memory_bytes() const = 0;
    virtual std::size_t nodes() const = 0;
    virtual std::size_t leaves() const = 0;
    /// Rays per packet of the packet path (8 or 16).
    virtual std::size_t packet_lanes() const = 0;
    /// Closest hit (any_hit = false) or any hit per ray, by `path` (single or packet; anything
    /// else is traced as single). Single-threaded; call from many threads on disjoint spans.
    /// Untraceable rays (ray_is_traceable) miss.
    virtual void trace(std::span<const Ray> rays, std::span<Hit> hits, TracePath path, bool any_hit) const = 0;
    /// Accel::trace_all and Accel::closest_points on this layout (wide_queries.h).
    virtual void trace_all(std::span<const Ray> rays, HitSink& sink) const = 0;
    virtual void closest_points(std::span<const Vec3f> points, float max_distance, std::span<PointHit> out) const = 0;
};

/// The width used when none is asked for: the measured best of this build (perf/results/wide-*.md).
std::uint32_t default_wide_width();
/// Rays per packet when none is asked for: 16 with AVX-512, else 8.
std::uint32_t default_packet_lanes();
/// Widths this build can trace: 4 and 8 always (x86-64-v3 or better), 16 with AVX-512.
bool wide_width_supported(std::uint32_t width);
/// The width a layout asked for `width` gets: `width` when supported, else default_wide_width().
std::uint32_t wide_width_or_default(std::uint32_t width);

/// Collapses `bvh` into `width`-wide nodes (0 = default_wide_width(); an unsupported width falls
/// back to the default) and returns its paths.
std::unique_ptr<WidePaths> make_wide_paths(std::uint32_t width, const BinaryBvh& bvh, const TriangleView& tris,
                                           const WideConfig& cfg = {});

}  // namespace arbor::accel
