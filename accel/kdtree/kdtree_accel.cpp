#include "accel/kdtree/kdtree_accel.h"

#include "accel/kdtree/kdtree_build.h"
#include "accel/kdtree/kdtree_queries.h"
#include "accel/kdtree/kdtree_traverse.h"
#include "accel/util/timer.h"
#include "simd/tri_test.h"

namespace arbor::accel {

KdTreeAccel::KdTreeAccel(const TriangleView& tris, const BuildConfig& cfg) {
    const Timer timer;
    tree_ = build_kdtree(tris, cfg);
    if (cfg.layouts != Layouts::scalar) simd_ = make_kd_simd_paths(tree_, cfg);
    stats_.build_ms = timer.ms();
    const KdTreeStats st = kd_tree_stats(tree_, cfg.traversal_cost, cfg.intersection_cost);
    stats_.triangles = tris.triangle_count();
    stats_.dropped_nonfinite = tree_.dropped_nonfinite;
    stats_.nodes = st.nodes;
    stats_.leaves = st.leaves;
    stats_.max_depth = st.max_depth;
    stats_.mean_leaf_depth = st.mean_leaf_depth;
    stats_.sah_cost = st.sah_cost;
    stats_.memory_bytes = tree_.memory_bytes() + (simd_ ? simd_->memory_bytes() : 0);
    stats_.build_peak_bytes = tree_.build_peak_bytes;
}

template <bool AnyHit, bool Count> Hit KdTreeAccel::trace(const Ray& ray, TraceCounters* counters) const {
    Hit best;
    if (!ray_is_traceable(ray)) return best;
    const simd::WoopShear shear = simd::woop_shear(ray.dir);
    float tfar = ray.tfar;
    std::uint64_t visited = 0, tested = 0;
    const auto leaf_fn = [&](std::uint32_t leaf_index) {
        const KdLeaf& leaf = tree_.leaves[leaf_index];
        if constexpr (Count) ++visited;
        for (std::uint32_t i = leaf.first, end = leaf.first + leaf.count; i < end; ++i) {
            const KdTriangle& tri = tree_.tris[tree_.refs[i]];
            if constexpr (Count) ++tested;
            const simd::TriHit<float> h = simd::woop_test(ray.org, shear, ray.tnear, tfar, tri.v0, tri.v1, tri.v2);
            if (!h.hit) continue;
            if constexpr (AnyHit) {
                best = {h.t, tri.prim, h.u, h.v};
                return true;
            }
            // woop_test accepts t == tfar: on equal t the lower prim wins, as in brute.
            if (h.t < best.t || !best.is_hit() || tri.prim < best.prim) {
                best = {h.t, tri.prim, h.u, h.v};
                tfar = h.t;
            }
        }
        return false;
    };
    kd::walk_ropes<AnyHit, Count>(tree_, ray, best.t, leaf_fn, visited);
    if constexpr (Count) {
        counters->nodes_visited += visited;
        counters->triangles_tested += tested;
    }
    return best;
}

template Hit KdTreeAccel::trace<false, false>(const Ray&, TraceCounters*) const;
template Hit KdTreeAccel::trace<true, false>(const Ray&, TraceCounters*) const;

bool KdTreeAccel::trace_counted(std::span<const Ray> rays, std::span<Hit> hits, bool any_hit,
                                TraceCounters& counters) const {
    counters.rays += rays.size();
    for (std::size_t i = 0; i < rays.size(); ++i)
        hits[i] = any_hit ? trace<true, true>(rays[i], &counters) : trace<false, true>(rays[i], &counters);
    return true;
}

TracePath KdTreeAccel::resolve_path(std::span<const Ray>, bool, std::string* reason) const {
    if (!simd_) {
        if (reason) *reason = "only the scalar path's layout was built";
        return TracePath::scalar;
    }
    // Measured (perf/results/kdtree-simd-2026-11-22.md): the packet path runs at 0.65-0.75x of the
    // single path on every kind of ray, coherent primary and shadow rays included, because each lane
    // still walks the ropes alone; only the triangle tests are shared.
    if (reason) *reason = "the kd-tree's packet path is slower than its single path on every kind of ray (measured)";
    return TracePath::single;
}

void KdTreeAccel::intersect(std::span<const Ray> rays, std::span<Hit> hits, TracePath path) const {
    if (path == TracePath::best || !has_path(path)) path = resolve_path(rays, false);
    if (path != TracePath::scalar) return simd_->trace(tree_, rays, hits, path, false);
    for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = trace<false>(rays[i]);
}

void KdTreeAccel::occluded(std::span<const Ray> rays, std::span<Hit> hits, TracePath path) const {
    if (path == TracePath::best || !has_path(path)) path = resolve_path(rays, true);
    if (path != TracePath::scalar) return simd_->trace(tree_, rays, hits, path, true);
    for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = trace<true>(rays[i]);
}

void KdTreeAccel::trace_all(std::span<const Ray> rays, HitSink& sink) const {
    std::vector<Hit> hits;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        hits.clear();
        all_hits_kdtree(tree_, rays[i], hits);
        sort_unique_hits(hits);
        sink.take(i, hits);
    }
}

void KdTreeAccel::closest_points(std::span<const Vec3f> points, float max_distance, std::span<PointHit> out) const {
    for (std::size_t i = 0; i < points.size(); ++i) {
        PointSearch s(points[i], max_distance);
        closest_point_kdtree(tree_, s);
        out[i] = s.result();
    }
}

}  // namespace arbor::accel
