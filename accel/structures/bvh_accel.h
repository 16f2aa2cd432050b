#pragma once
/// BvhAccel: every binary BVH (bvh-median, bvh-sah, lbvh) behind the Accel interface. It converts
/// the builder's BinaryBvh into Bvh2Layout (bvh2_layout.h) for the scalar reference path (the loop
/// of bvh2_traverse.h and the watertight test of simd/ray_triangle.h, exactly as `brute` does). A build
/// with the SIMD layouts is a WideBvhAccel<N> (wide_paths_impl.h): this class plus an N-wide
/// layout collapsed from the same binary tree, and the paths `single` and `packet` over it.
#include "accel/interface/accel.h"
#include "accel/bvh/binary_bvh.h"
#include "accel/bvh/bvh2_layout.h"
#include "accel/bvh/build_prims.h"
#include "accel/bvh/prim_refs.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace arbor::accel {

/// The shape of a BVH's SIMD layout (all 0 when only the scalar layout was built).
struct WideShape {
    std::size_t width = 0;         ///< children per node (4, 8 or 16)
    std::size_t nodes = 0, leaves = 0;
    std::size_t memory_bytes = 0;  ///< nodes, triangle blocks, ids and child orders
};

class BvhAccel : public Accel {
public:
    /// A build with the scalar layout only: converts `bvh` (built over `tris`) to it. `build_ms`
    /// is the time spent before (prim refs + builder); the conversion time is added.
    BvhAccel(AccelKind kind, const BinaryBvh& bvh, const TriangleView& tris, const BuildConfig& cfg, double build_ms);

    /// One ray through the scalar loop (needs the scalar layout): the closest hit, or any hit.
    Hit trace_one(const Ray& ray, Query query) const;
    /// On the scalar layout (bvh2_queries.h); WideBvhAccel answers on its SIMD layout
    /// (wide_queries.h).
    void trace_all(std::span<const Ray> rays, HitSink& sink) const override;
    void closest_points(std::span<const Vec3f> points, float max_distance, std::span<PointHit> out) const override;
    /// Dipoles on the scalar layout (bvh/bvh2_winding.h); WideBvhAccel puts them on its SIMD
    /// layout (wide/wide_winding.h).
    std::unique_ptr<WindingTree> make_winding_tree(const TriangleView& tris) const override;
    const Bvh2Layout& layout() const { return layout_; }

    /// The binary BVHs refit (bvh/bvh2_refit.h; WideBvhAccel adds its SIMD layout). A BVH made from
    /// the kd-tree's cells (KdCellAccel) does not: its boxes are the cells'.
    std::string_view refit_unsupported() const override;
    RefitResult refit(const TriangleView& tris) override;
    const WideShape& wide_shape() const { return wide_; }

protected:
    explicit BvhAccel(AccelKind kind) : Accel(kind) {}
    /// The constructor's work, for WideBvhAccel's constructor too: the scalar layout (when
    /// cfg.layouts asks for it), `make_wide(wide)` (the SIMD layout, when given, made with `wide`:
    /// cfg.wide, its max_bytes set) and the tree's statistics are made side by side, all only
    /// reading the binary tree. With cfg.max_memory set, wide.max_bytes is what the binary tree,
    /// the conversion's words and the scalar layout leave of it: MemoryLimitError (naming the
    /// structure) before a layout that would not fit is made.
    void init(const BinaryBvh& bvh, const TriangleView& tris, const BuildConfig& cfg, double build_ms,
              const std::function<WideShape(const WideConfig& wide)>& make_wide);

    /// The scalar path and the counted mode (the scalar loop's counting instantiation).
    void run(std::span<const Ray> rays, std::span<Hit> hits, Query query, TracePath path,
             TraceCounters* counters) const override;
    void run_scalar(std::span<const Ray> rays, std::span<Hit> hits, Query query, TraceCounters* counters) const;
    /// refit()'s work on the layouts: the scalar one here; WideBvhAccel refits its SIMD layout and
    /// returns that layout's SAH cost (else the scalar layout's). `bounds`: the root's box after it.
    virtual double refit_layouts(const TriangleView& tris, Bounds& bounds);
    /// The SAH cost refit() compares against, of the layout it reports (set after the build).
    double built_sah_ = 0.0;

private:
    /// The scalar loop over a batch; with Count, what it did is added to *counters.
    template <bool AnyHit, bool Count = false>
    void trace_batch(std::span<const Ray> rays, std::span<Hit> hits, TraceCounters* counters = nullptr) const;

    Bvh2Layout layout_;
    WideShape wide_;
};

/// A BVH builder: a pure function of the prim refs and the config.
using BvhBuilder = BinaryBvh (*)(const PrimRefs&, const BvhBuildConfig&);
/// The same builder on build prims it consumes (build_prims.h): what the factory calls.
using BvhPrimBuilder = BinaryBvh (*)(BuildPrims&&, const BvhBuildConfig&);

/// What a conversion of `bvh` into layouts holds besides the layouts themselves: the binary tree
/// (its nodes and ids) and the converter's three words per node. BvhAccel::init checks the
/// layouts against the limit, and counts the conversion's peak, with these bytes.
std::size_t conversion_held_bytes(const BinaryBvh& bvh);

/// Throws MemoryLimitError ("bvh-sah: building its binary tree reached ...") when max_memory is set
/// and the binary tree's build peaked above it (the lbvh's, which is not counted as it grows).
void check_binary_peak(AccelKind kind, const BinaryBvh& bvh, std::uint64_t max_memory);

/// What a BVH build with `cfg` offers (the paths and queries; the path policy reads it), before
/// building: the scalar path with the scalar layout, `single` and `packet` with the SIMD layouts.
PathOffer bvh_offer(const BuildConfig& cfg);
/// The work a BVH build with `cfg` leaves out, in words: the layouts no path of it reads, and the
/// binary splits below `leaf_floor` triangles (factory/make_accel.h, bvh_leaf_floor).
std::vector<std::string> bvh_skipped(const BuildConfig& cfg, std::uint32_t leaf_floor);

}  // namespace arbor::accel
