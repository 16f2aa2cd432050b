#pragma once
/// `kdtree`: the SAH kd-tree with ropes (kdtree_build.h) and its stackless scalar traversal
/// (kdtree_traverse.h).
#include "accel/accel.h"
#include "accel/kdtree_node.h"

namespace arbor::accel {

class KdTreeAccel final : public Accel {
public:
    /// Builds the tree (copies what it needs; the view may go away afterwards).
    KdTreeAccel(const TriangleView& tris, const BuildConfig& cfg = {});

    AccelKind kind() const override { return AccelKind::kdtree; }
    const BuildStats& stats() const override { return stats_; }
    void intersect(std::span<const Ray> rays, std::span<Hit> hits, TracePath path) const override;
    void occluded(std::span<const Ray> rays, std::span<Hit> hits, TracePath path) const override;

    bool trace_counted(std::span<const Ray> rays, std::span<Hit> hits, bool any_hit,
                       TraceCounters& counters) const override;

    /// One ray along the ropes: the closest hit (on equal t the lower prim), or any hit. Count:
    /// adds nodes (interior nodes tested, leaves entered) and triangle tests to `counters`.
    template <bool AnyHit, bool Count = false> Hit trace(const Ray& ray, TraceCounters* counters = nullptr) const;
    const KdTree& tree() const { return tree_; }

private:
    KdTree tree_;
    BuildStats stats_;
};

}  // namespace arbor::accel
