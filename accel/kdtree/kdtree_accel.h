#pragma once
/// `kdtree`: the SAH kd-tree with ropes (kdtree_build.h), its stackless scalar traversal
/// (kdtree_traverse.h) and its SIMD paths `single` and `packet` (kdtree_simd.h).
#include "accel/accel.h"
#include "accel/kdtree/kdtree_node.h"
#include "accel/kdtree/kdtree_simd.h"

#include <memory>

namespace arbor::accel {

class KdTreeAccel final : public Accel {
public:
    /// Builds the tree (copies what it needs; the view may go away afterwards).
    KdTreeAccel(const TriangleView& tris, const BuildConfig& cfg = {});

    AccelKind kind() const override { return AccelKind::kdtree; }
    const BuildStats& stats() const override { return stats_; }
    /// packet and single need the SIMD leaf blocks (BuildConfig::layouts != scalar).
    bool has_path(TracePath path) const override { return simd_ || path == TracePath::scalar || path == TracePath::best; }
    /// `single` for every batch: the packet path measured slower on every kind of ray, coherent
    /// ones included (perf/results/kdtree-simd-2026-11-22.md).
    TracePath resolve_path(std::span<const Ray> rays, bool any_hit, std::string* reason = nullptr) const override;
    void intersect(std::span<const Ray> rays, std::span<Hit> hits, TracePath path) const override;
    void occluded(std::span<const Ray> rays, std::span<Hit> hits, TracePath path) const override;
    /// The rope walk with every hit kept (kdtree_queries.h).
    void trace_all(std::span<const Ray> rays, HitSink& sink) const override;
    /// Depth-first over the cells, the nearer first (kdtree_queries.h).
    void closest_points(std::span<const Vec3f> points, float max_distance, std::span<PointHit> out) const override;

    bool trace_counted(std::span<const Ray> rays, std::span<Hit> hits, bool any_hit,
                       TraceCounters& counters) const override;

    /// One ray along the ropes: the closest hit (on equal t the lower prim), or any hit. Count:
    /// adds nodes (interior nodes tested, leaves entered) and triangle tests to `counters`.
    template <bool AnyHit, bool Count = false> Hit trace(const Ray& ray, TraceCounters* counters = nullptr) const;
    const KdTree& tree() const { return tree_; }
    const KdSimdPaths& simd_paths() const { return *simd_; }

private:
    KdTree tree_;
    std::unique_ptr<KdSimdPaths> simd_;
    BuildStats stats_;
};

}  // namespace arbor::accel
