// CompactBvhAccel<N>: a BVH traced on its compact layout (wide/compact_layout.h), the build of
// BuildConfig::compact (`--compact`). Compiled once per kernel set (cmake/ArborKernelSets.cmake),
// reached through kset::make_wide_bvh_accel (wide_paths.h).
//
// Paths: `single` only (closest and any hit through the walk of wide_traverse.h with the compact
// node and leaf tests, compact_traverse.h); a request for `packet` or `scalar` is traced on it
// (the path policy's rule for a path not offered), and the counted mode is not offered. All hits
// use the same walk; closest points test every leaf triangle (no pruning by the tree); winding
// numbers build their own tree (Accel::make_winding_tree). No refit.
#include <algorithm>
#include <utility>
#include <vector>

#include "accel/core/hit_record.h"
#include "accel/structures/bvh_accel.h"
#include "accel/structures/wide_paths.h"
#include "accel/wide/compact_layout.h"
#include "accel/wide/compact_traverse.h"
#include "accel/wide/wide_push.h"
#include "simd/wide_ray_setup.h"

namespace arbor::accel {

namespace {

template <std::size_t N>
class CompactBvhAccel final : public BvhAccel {
public:
    using T = WideLane<N>;

    CompactBvhAccel(AccelKind kind, const BinaryBvh& bvh, const TriangleView& tris, const BuildConfig& cfg,
                    double build_ms)
        : BvhAccel(kind) {
        BuildConfig only = cfg;
        only.layouts = Layouts::simd;  // (the scalar layout would cost more than the compact one saves)
        std::size_t wide_bytes = 0;
        init(bvh, tris, only, build_ms, [&] {
            WideLayout<N> wide = make_wide_layout<N>(bvh, tris, cfg.wide);
            wide_bytes = wide.memory_bytes();
            layout_ = make_compact_layout<N>(std::move(wide), tris);
            return WideShape{N, layout_.nodes.size(), layout_.leaves, layout_.memory_bytes()};
        });
        // The conversion holds the binary tree, the wide layout and the compact one at once (the
        // peak init worked out counts the compact layout only).
        const std::size_t binary_bytes =
            bvh.nodes.capacity() * sizeof(BvhBuildNode) + bvh.prim_ids.capacity() * sizeof(std::uint32_t);
        stats_.build_peak_bytes = std::max(stats_.build_peak_bytes, binary_bytes + wide_bytes + stats_.memory_bytes);
        offer_.add(TracePath::single);
        offer_.packets_pay = false;
    }

    std::string_view refit_unsupported() const override { return "the compact layout has no refit"; }
    RefitResult refit(const TriangleView& tris) override { return Accel::refit(tris); }

    std::unique_ptr<WindingTree> make_winding_tree(const TriangleView& tris) const override {
        return Accel::make_winding_tree(tris);
    }

    void trace_all(std::span<const Ray> rays, HitSink& sink) const override {
        WideStack stack(layout_.stack_size());
        std::vector<Hit> hits;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            hits.clear();
            const Ray& ray = rays[i];
            simd::WideRay<T> r = simd::wide_ray<T>(ray.org, ray.dir, ray.tnear, ray.tfar);
            if (!layout_.empty() && r.traceable) {
                auto leaf = [&](std::uint32_t first, std::uint32_t n) {
                    for (std::uint32_t b = 0; b < n; b += N) {
                        const simd::TriHit<T> h = compact_triangles<T>(r, layout_, first, n, b);
                        for (std::uint32_t bits = simd::to_bits(h.hit); bits != 0; bits &= bits - 1) {
                            const auto l = std::size_t(std::countr_zero(bits));
                            hits.push_back({simd::lane(h.t, l), layout_.prim(first, n, b + std::uint32_t(l)),
                                            simd::lane(h.u, l), simd::lane(h.v, l)});
                        }
                    }
                    return false;  // never shortened
                };
                if (r.plain)
                    detail::walk_wide<false, true, false>(layout_, r, ray.tfar, stack, 0, 0, 0, T(0.0f), 0, nullptr,
                                                          leaf);
                else
                    detail::walk_wide<false, false, false>(layout_, r, ray.tfar, stack, 0, 0, 0, T(0.0f), 0, nullptr,
                                                           leaf);
            }
            sort_unique_hits(hits);
            sink.take(i, hits);
        }
    }

    void closest_points(std::span<const Vec3f> points, float max_distance, std::span<PointHit> out) const override {
        for (std::size_t i = 0; i < points.size(); ++i) {
            PointSearch s(points[i], max_distance);
            if (s.searchable())
                for (const CompactNode<N>& node : layout_.nodes)
                    for (std::size_t c = 0; c < node.children; ++c) {
                        const std::uint32_t first = node.child[c], n = node.count[c];
                        for (std::uint32_t t = 0; t < n; ++t)
                            s.offer(layout_.vertex(first, n, t, 0), layout_.vertex(first, n, t, 1),
                                    layout_.vertex(first, n, t, 2), layout_.prim(first, n, t));
                    }
            out[i] = s.result();
        }
    }

protected:
    double refit_layouts(const TriangleView&, Bounds&) override { return 0.0; }

private:
    /// Ray r's test of the leaf (first, n): hits offered to `best`; a kept hit lowers
    /// tfar and r.tfar (and ends the leaf for AnyHit). True when one was kept.
    template <bool AnyHit>
    ARBOR_INLINE bool test_leaf(simd::WideRay<T>& r, float& tfar, HitRecord<AnyHit>& best, std::uint32_t first,
                                std::uint32_t n) const {
        bool found = false;
        for (std::uint32_t b = 0; b < n; b += N) {
            const simd::TriHit<T> h = compact_triangles<T>(r, layout_, first, n, b);
            const std::uint32_t bits = simd::to_bits(h.hit);
            if (bits == 0) continue;
            // The lowest lane among equal t: the lowest prim (the leaf is in ascending prim order;
            // the lanes past its end are NaN padding, which never hits).
            const int lane = AnyHit ? std::countr_zero(bits) : simd::closest_lane<T>(h.hit, h.t);
            const float t = simd::lane(h.t, std::size_t(lane));
            if (!best.offer(t, layout_.prim(first, n, b + std::uint32_t(lane)), simd::lane(h.u, std::size_t(lane)),
                            simd::lane(h.v, std::size_t(lane))))
                continue;
            tfar = t;
            r.tfar = T(t);
            found = true;
            if constexpr (AnyHit) return true;
        }
        return found;
    }

    template <bool AnyHit>
    Hit walk_ray(simd::WideRay<T>& r, float tfar, WideStack& stack) const {
        HitRecord<AnyHit> best;
        // (Forced inline: as a call, the walk's WideRay lived in memory and every node test reloaded it.)
        const auto leaf = [&](std::uint32_t first, std::uint32_t n) __attribute__((always_inline)) {
            return test_leaf(r, tfar, best, first, n);
        };
        if (r.plain)
            detail::walk_wide<AnyHit, true, false>(layout_, r, tfar, stack, 0, 0, 0, T(0.0f), 0, nullptr, leaf);
        else
            detail::walk_wide<AnyHit, false, false>(layout_, r, tfar, stack, 0, 0, 0, T(0.0f), 0, nullptr, leaf);
        return best.hit;
    }

    template <bool AnyHit>
    void trace_single(std::span<const Ray> rays, std::span<Hit> hits) const {
        if (layout_.empty()) {
            std::fill(hits.begin(), hits.end(), Hit{});
            return;
        }
        WideStack stack(layout_.stack_size());
        simd::WideRaySetup<simd::SetupLane> setup;
        simd::WideRay<T> r;
        for (std::size_t base = 0; base < rays.size(); base += setup.size) {
            const auto in = rays.subspan(base, std::min(setup.size, rays.size() - base));
            simd::wide_ray_setup(in, setup);
            for (std::size_t i = 0; i < in.size(); ++i) {
                setup.get(i, r);
                hits[base + i] = r.traceable ? walk_ray<AnyHit>(r, in[i].tfar, stack) : Hit{};
            }
        }
    }

    void run(std::span<const Ray> rays, std::span<Hit> hits, Query query, TracePath,
             TraceCounters* counters) const override {
        if (counters)
            return BvhAccel::run(rays, hits, query, TracePath::scalar, counters);  // (check_counts threw before)
        if (query == Query::any)
            trace_single<true>(rays, hits);
        else
            trace_single<false>(rays, hits);
    }

    CompactLayout<N> layout_;
};

}  // namespace

namespace kset {

std::unique_ptr<Accel> make_compact_bvh_accel(std::uint32_t width, AccelKind kind, const BinaryBvh& bvh,
                                              const TriangleView& tris, const BuildConfig& cfg, double build_ms) {
    switch (width) {
#if XSIMD_WITH_AVX2
        case 8:
            return std::make_unique<CompactBvhAccel<8>>(kind, bvh, tris, cfg, build_ms);
#endif
#if XSIMD_WITH_AVX512F
        case 16:
            return std::make_unique<CompactBvhAccel<16>>(kind, bvh, tris, cfg, build_ms);
#endif
        default:
            break;
    }
    return std::make_unique<CompactBvhAccel<4>>(kind, bvh, tris, cfg, build_ms);
}

}  // namespace kset

}  // namespace arbor::accel
