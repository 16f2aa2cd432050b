#include "accel/structures/brute_accel.h"

#include "accel/core/hit_record.h"
#include "accel/util/timer.h"
#include "simd/ray_triangle.h"

namespace arbor::accel {

BruteAccel::BruteAccel(const TriangleView& view) : Accel(AccelKind::brute) {
    const Timer timer;
    stats_.triangles = view.triangle_count();
    tris_.reserve(stats_.triangles);
    for (std::size_t i = 0; i < stats_.triangles; ++i) {
        if (!view.triangle_is_finite(i)) {
            ++stats_.dropped_nonfinite;
            continue;
        }
        tris_.push_back({view.corner(i, 0), view.corner(i, 1), view.corner(i, 2), std::uint32_t(i)});
    }
    stats_.nodes = 1;
    stats_.leaves = 1;
    stats_.sah_cost = double(tris_.size());  // every ray tests every triangle
    stats_.memory_bytes = tris_.capacity() * sizeof(Tri);
    stats_.build_ms = timer.ms();
    offer_.add(TracePath::scalar);
    offer_.counts = true;
}

RefitResult BruteAccel::refit(const TriangleView& view) {
    const Timer timer;
    RefitResult r;
    for (Tri& tri : tris_) {
        tri.v0 = view.corner(tri.prim, 0), tri.v1 = view.corner(tri.prim, 1), tri.v2 = view.corner(tri.prim, 2);
        r.bounds.grow(tri.v0), r.bounds.grow(tri.v1), r.bounds.grow(tri.v2);
    }
    r.sah_cost = r.built_sah_cost = stats_.sah_cost;  // the same work for every ray, wherever the triangles are
    r.ms = timer.ms();
    return r;
}

Hit BruteAccel::trace_one(const Ray& ray, Query query) const {
    return query == Query::any ? trace_impl<true, false>(ray, nullptr) : trace_impl<false, false>(ray, nullptr);
}

template <bool AnyHit, bool Count> Hit BruteAccel::trace_impl(const Ray& ray, TraceCounters* counters) const {
    HitRecord<AnyHit> best;
    if constexpr (Count) ++counters->rays;
    if (!ray_is_traceable(ray)) return best.hit;
    if constexpr (Count) ++counters->nodes_visited;
    const simd::WoopShear shear = simd::woop_shear(ray.dir);
    float tfar = ray.tfar;
    for (const Tri& tri : tris_) {
        if constexpr (Count) ++counters->triangles_tested;
        const simd::TriHit<float> h = simd::woop_test(ray.org, shear, ray.tnear, tfar, tri.v0, tri.v1, tri.v2);
        if (h.hit && best.offer(h.t, tri.prim, h.u, h.v)) {
            if constexpr (AnyHit) return best.hit;
            tfar = h.t;
        }
    }
    return best.hit;
}

void BruteAccel::run(std::span<const Ray> rays, std::span<Hit> hits, Query query, TracePath,
                     TraceCounters* counters) const {
    const auto each = [&](auto one) {
        for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = one(rays[i]);
    };
    const bool any = query == Query::any;
    if (counters && any) each([&](const Ray& r) { return trace_impl<true, true>(r, counters); });
    else if (counters) each([&](const Ray& r) { return trace_impl<false, true>(r, counters); });
    else if (any) each([&](const Ray& r) { return trace_impl<true, false>(r, nullptr); });
    else each([&](const Ray& r) { return trace_impl<false, false>(r, nullptr); });
}

void BruteAccel::trace_all(std::span<const Ray> rays, HitSink& sink) const {
    std::vector<Hit> hits;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        hits.clear();
        const Ray& ray = rays[i];
        if (ray_is_traceable(ray)) {
            const simd::WoopShear shear = simd::woop_shear(ray.dir);
            for (const Tri& tri : tris_) {
                const simd::TriHit<float> h = simd::woop_test(ray.org, shear, ray.tnear, ray.tfar, tri.v0, tri.v1, tri.v2);
                if (h.hit) hits.push_back({h.t, tri.prim, h.u, h.v});
            }
            sort_unique_hits(hits);
        }
        sink.take(i, hits);
    }
}

void BruteAccel::closest_points(std::span<const Vec3f> points, float max_distance, std::span<PointHit> out) const {
    for (std::size_t i = 0; i < points.size(); ++i) {
        PointSearch s(points[i], max_distance);
        if (s.searchable())
            for (const Tri& tri : tris_) s.offer(tri.v0, tri.v1, tri.v2, tri.prim);
        out[i] = s.result();
    }
}

PathOffer brute_offer() {
    PathOffer o;
    o.add(TracePath::scalar), o.counts = true;
    return o;
}

std::unique_ptr<WindingTree> BruteAccel::make_winding_tree(const TriangleView& tris) const {
    return make_exact_winding(tris);
}

}  // namespace arbor::accel
