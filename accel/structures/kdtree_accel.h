#pragma once
/// `kdtree`: the SAH kd-tree with ropes (kdtree_build.h) and its scalar traversals: stackless along
/// the ropes for closest hit (kdtree_traverse.h), the front-to-back stack walk for any hit
/// (kdtree_stack.h, the order the packet walk keeps). A build with the SIMD layouts is a KdSimdAccel<N> (kdtree_simd.h): this
/// class plus the leaves' triangles in SIMD blocks of N, and the paths `single` and `packet`.
#include "accel/interface/accel.h"
#include "accel/kdtree/kdtree_node.h"

#include <memory>
#include <string>
#include <vector>

namespace arbor::accel {

class KdTreeAccel : public Accel {
public:
    /// One ray: the closest hit along the ropes (on equal t the lower prim), or any hit by the
    /// stack walk (the first hit in its order). Count:
    /// adds nodes (interior nodes tested, leaves entered) and triangle tests to `counters`.
    template <bool AnyHit, bool Count = false> Hit trace_one(const Ray& ray, TraceCounters* counters = nullptr) const;
    const KdTree& tree() const { return tree_; }
    /// The rope walk with every hit kept (kdtree_queries.h).
    void trace_all(std::span<const Ray> rays, HitSink& sink) const override;
    /// Depth-first over the cells, the nearer first (kdtree_queries.h).
    void closest_points(std::span<const Vec3f> points, float max_distance, std::span<PointHit> out) const override;
    /// Triangles per SIMD block of the SIMD paths (0: built without them).
    std::uint32_t simd_block_width() const { return block_width_; }
    /// The layout the SIMD paths trace (ropes also when built without them).
    virtual KdWalk walk() const { return KdWalk::ropes; }
    /// With the cell walk: the wide BVH of the cells that the SIMD paths trace (kdtree_cells.h).
    virtual const Accel* cell_paths() const { return nullptr; }
    /// Never: a refit keeps a tree's splits, and a kd-tree's splits are planes that partition the
    /// triangles, so once the triangles move, a plane may cut a triangle its cell does not list.
    std::string_view refit_unsupported() const override {
        return "a kd-tree's split planes cannot be refit (moved triangles cross them)";
    }

protected:
    /// Takes over `tree` (built with `cfg`, in `build_ms`) for its scalar path.
    KdTreeAccel(KdTree&& tree, const BuildConfig& cfg, double build_ms);
    /// The factory (factory/make_kdtree.cpp) makes the scalar-only kd-tree.
    friend std::unique_ptr<KdTreeAccel> make_kdtree_accel(KdTree tree, const BuildConfig& cfg, double build_ms);

    /// The scalar path and the counted mode.
    void run(std::span<const Ray> rays, std::span<Hit> hits, Query query, TracePath path,
             TraceCounters* counters) const override;
    void run_scalar(std::span<const Ray> rays, std::span<Hit> hits, Query query, TraceCounters* counters) const;

    KdTree tree_;
    std::uint32_t block_width_ = 0;
};

/// What a kd-tree build with `cfg` offers, before building: the scalar path always (it reads the
/// tree itself, which every build makes), `single` and `packet` with the SIMD layouts.
PathOffer kdtree_offer(const BuildConfig& cfg);
/// The work a kd-tree build with `cfg` leaves out, in words.
std::vector<std::string> kdtree_skipped(const BuildConfig& cfg);

}  // namespace arbor::accel
