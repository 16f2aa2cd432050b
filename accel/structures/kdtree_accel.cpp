#include "accel/structures/kdtree_accel.h"

#include "accel/core/hit_record.h"
#include "accel/kdtree/kdtree_build.h"
#include "accel/kdtree/kdtree_queries.h"
#include "accel/kdtree/kdtree_stack.h"
#include "accel/kdtree/kdtree_traverse.h"
#include "accel/util/timer.h"
#include "simd/ray_triangle.h"

namespace arbor::accel {

KdTreeAccel::KdTreeAccel(KdTree&& tree, const BuildConfig& cfg, double build_ms) : Accel(AccelKind::kdtree), tree_(std::move(tree)) {
    stats_.build_ms = build_ms;
    const KdTreeStats st = kd_tree_stats(tree_, cfg.kd.reported_traversal_cost, cfg.kd.intersection_cost);
    stats_.triangles = tree_.tris.size() + tree_.dropped_nonfinite;  // the view's count
    stats_.dropped_nonfinite = tree_.dropped_nonfinite;
    stats_.nodes = st.nodes;
    stats_.leaves = st.leaves;
    stats_.max_depth = st.max_depth;
    stats_.mean_leaf_depth = st.mean_leaf_depth;
    stats_.sah_cost = st.sah_cost;
    stats_.memory_bytes = tree_.memory_bytes();
    stats_.build_peak_bytes = tree_.build_peak_bytes;
    // The tree itself is the scalar path's layout: every build has it.
    offer_.add(TracePath::scalar);
    offer_.counts = true;
    offer_.simd_skipped = true;  // until a KdSimdAccel adds its paths
}

template <bool AnyHit, bool Count> Hit KdTreeAccel::trace_one(const Ray& ray, TraceCounters* counters) const {
    HitRecord<AnyHit> best;
    if (!ray_is_traceable(ray)) return best.hit;
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
            if (!h.hit || !best.offer(h.t, tri.prim, h.u, h.v)) continue;
            if constexpr (AnyHit) return true;
            tfar = h.t;
        }
        return false;
    };
    // Any hit: the front-to-back stack walk, whose leaf order the packet path keeps lane by lane
    // (kdtree_stack_packet.h); closest hit: the ropes (the answer does not depend on the order).
    if constexpr (AnyHit) kd::walk_stack<true, Count>(tree_, ray, best.hit.t, leaf_fn, visited);
    else kd::walk_ropes<false, Count>(tree_, ray, best.hit.t, leaf_fn, visited);
    if constexpr (Count) {
        counters->nodes_visited += visited;
        counters->triangles_tested += tested;
    }
    return best.hit;
}

template Hit KdTreeAccel::trace_one<false, false>(const Ray&, TraceCounters*) const;
template Hit KdTreeAccel::trace_one<true, false>(const Ray&, TraceCounters*) const;

void KdTreeAccel::run(std::span<const Ray> rays, std::span<Hit> hits, Query query, TracePath, TraceCounters* counters) const {
    run_scalar(rays, hits, query, counters);
}

void KdTreeAccel::run_scalar(std::span<const Ray> rays, std::span<Hit> hits, Query query, TraceCounters* counters) const {
    const bool any_hit = query == Query::any;
    if (counters) {
        counters->rays += rays.size();
        for (std::size_t i = 0; i < rays.size(); ++i)
            hits[i] = any_hit ? trace_one<true, true>(rays[i], counters) : trace_one<false, true>(rays[i], counters);
        return;
    }
    for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = any_hit ? trace_one<true>(rays[i]) : trace_one<false>(rays[i]);
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
        PointSearch s(points[i], i == 0 ? max_distance : warm_reach(points[i], out[i - 1], max_distance));
        closest_point_kdtree(tree_, s);
        out[i] = s.result();
    }
}

PathOffer kdtree_offer(const BuildConfig& cfg) {
    PathOffer o;
    const bool simd = cfg.layouts != Layouts::scalar;
    o.add(TracePath::scalar), o.counts = true, o.simd_skipped = !simd;
    if (simd) o.add(TracePath::single), o.add(TracePath::packet), o.packets_pay = true;
    return o;
}

std::vector<std::string> kdtree_skipped(const BuildConfig& cfg) {
    // The scalar path reads the tree itself, which every build makes: only the SIMD layouts can be left out.
    if (cfg.layouts == Layouts::scalar) return {"SIMD layouts (only the SIMD paths read them)"};
    return {};
}

}  // namespace arbor::accel
