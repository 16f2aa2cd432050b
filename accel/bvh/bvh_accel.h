#pragma once
/// BvhAccel: every binary BVH (bvh-median, bvh-sah, lbvh) behind the Accel interface. It converts
/// the builder's BinaryBvh into Bvh2Layout (bvh2_layout.h), the scalar reference path (the loop of
/// bvh2_traverse.h and the watertight test of simd/tri_test.h, exactly as `brute` does), and into an
/// N-wide layout for the SIMD paths `single` and `packet` (wide_paths.h).
#include "accel/accel.h"
#include "accel/bvh/binary_bvh.h"
#include "accel/bvh/bvh2_layout.h"
#include "accel/bvh/prim_refs.h"
#include "accel/wide/wide_paths.h"

#include <memory>

namespace arbor::accel {

class BvhAccel final : public Accel {
public:
    /// Converts `bvh` (built over `tris`) to the traversal layout. The BinaryBvh is alive for the
    /// whole constructor: layouts collapsed from the binary tree (wide nodes) are made here too.
    /// `build_ms` is the time spent before (prim refs + builder); the conversion time is added.
    BvhAccel(AccelKind kind, BinaryBvh&& bvh, const TriangleView& tris, const BuildConfig& cfg, double build_ms);

    AccelKind kind() const override { return kind_; }
    /// scalar: when the scalar layout was built; packet and single: when the wide layout was
    /// (BuildConfig::layouts). A path without its layout is traced on the one `best` takes.
    bool has_path(TracePath path) const override;
    /// `packet` when at least half of the groups of consecutive rays that would share a packet are
    /// coherent (accel/select/coherence.h: one direction octant, origins within 5% of the scene's
    /// diagonal), else `single` (measured: perf/results/wide-*.md).
    TracePath resolve_path(std::span<const Ray> rays, bool any_hit, std::string* reason = nullptr) const override;
    const BuildStats& stats() const override { return stats_; }
    void intersect(std::span<const Ray> rays, std::span<Hit> hits, TracePath path) const override;
    void occluded(std::span<const Ray> rays, std::span<Hit> hits, TracePath path) const override;
    /// On the SIMD layout when it was built, else on the scalar one (wide_queries.h, bvh2_queries.h).
    void trace_all(std::span<const Ray> rays, HitSink& sink) const override;
    void closest_points(std::span<const Vec3f> points, float max_distance, std::span<PointHit> out) const override;
    bool trace_counted(std::span<const Ray> rays, std::span<Hit> hits, bool any_hit,
                       TraceCounters& counters) const override;

    /// One ray through the scalar loop (needs the scalar layout): closest hit, or with any_hit the
    /// first hit found.
    Hit trace(const Ray& ray, bool any_hit) const;
    const Bvh2Layout& layout() const { return layout_; }
    /// The SIMD paths (needs the wide layout).
    const WidePaths& wide() const { return *wide_; }

private:
    /// The scalar loop over a batch; with Count, what it did is added to *counters.
    template <bool AnyHit, bool Count = false>
    void trace_batch(std::span<const Ray> rays, std::span<Hit> hits, TraceCounters* counters = nullptr) const;

    AccelKind kind_;
    Bvh2Layout layout_;
    bool has_scalar_ = true;
    std::unique_ptr<WidePaths> wide_;  ///< null when only the scalar layout was built
    float diagonal_ = 0.0f;  ///< of the root box (the coherence measure's scale)
    BuildStats stats_;
};

/// The Accel for any BinaryBvh; see BvhAccel.
std::unique_ptr<Accel> make_bvh_accel(AccelKind kind, BinaryBvh&& bvh, const TriangleView& tris,
                                      const BuildConfig& cfg, double build_ms);

/// A BVH builder: a pure function of the prim refs and the config.
using BvhBuilder = BinaryBvh (*)(const PrimRefs&, const BuildConfig&);

/// The BuildConfig::leaf_floor a BVH build with `cfg` gets: for builds of the SIMD layouts only,
/// cfg.simd_leaf_floor with 0 read as the SIMD layout's width; else 0 (no floor).
std::uint32_t bvh_leaf_floor(const BuildConfig& cfg);

/// PrimRefs -> `builder` -> BvhAccel, timed as a whole (build_ms covers all three steps); the
/// builder sees cfg with leaf_floor = bvh_leaf_floor(cfg).
std::unique_ptr<Accel> build_bvh_accel(AccelKind kind, const TriangleView& tris, const BuildConfig& cfg,
                                       BvhBuilder builder);

}  // namespace arbor::accel
