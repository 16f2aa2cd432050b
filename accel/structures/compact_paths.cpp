// CompactBvhAccel<N>: a BVH traced on its compact layout (wide/compact_layout.h), the build of
// BuildConfig::compact (`--compact`). Compiled once per kernel set (cmake/ArborKernelSets.cmake),
// reached through kset::make_wide_bvh_accel (wide_paths.h).
//
// Paths: `single` (closest and any hit through the walk of wide_traverse.h with the compact node
// and leaf tests, compact_traverse.h) and `packet` (the packet walk of wide_packet.h: a node's
// planes decoded once for all lanes, a leaf's vertices gathered into a block once for all lanes);
// a request for `scalar` is traced on `best` (the path policy's rule for a path not offered), and
// the counted mode is not offered. All hits
// use the same walk; closest points test every leaf triangle (no pruning by the tree); winding
// numbers build their own tree (Accel::make_winding_tree). No refit.
#include <algorithm>
#include <utility>
#include <vector>

#include "accel/core/hit_record.h"
#include "accel/core/simd_paths.h"
#include "accel/structures/bvh_accel.h"
#include "accel/structures/wide_paths.h"
#include "accel/util/stack_buffer.h"
#include "accel/wide/compact_layout.h"
#include "accel/wide/compact_traverse.h"
#include "accel/wide/wide_packet.h"
#include "accel/wide/wide_push.h"
#include "accel/wide/wide_root.h"
#include "simd/packet_bounds.h"
#include "simd/wide_ray_setup.h"

namespace arbor::accel {

namespace {

template <std::size_t N>
class CompactBvhAccel final : public BvhAccel, public SimdPaths<CompactBvhAccel<N>> {
    friend class SimdPaths<CompactBvhAccel<N>>;

public:
    using T = WideLane<N>;

    CompactBvhAccel(AccelKind kind, const BinaryBvh& bvh, const TriangleView& tris, const BuildConfig& cfg,
                    double build_ms)
        : BvhAccel(kind), SimdPaths<CompactBvhAccel<N>>(resolve_packets(cfg.packets)) {
        BuildConfig only = cfg;
        only.layouts = Layouts::simd;  // (the scalar layout would cost more than the compact one saves)
        std::size_t wide_bytes = 0, scratch_bytes = 0;
        init(bvh, tris, only, build_ms, [&](const WideConfig& wide_cfg) {
            // (The compact leaves read their vertices from the mesh: the source needs no blocks.)
            // Its plan is checked against the limit, and the compact layout from its sizes, with
            // the source beside it, before each is allocated.
            WideLayout<N> wide = make_wide_layout<N>(bvh, tris, wide_cfg, WideLeaves::ids);
            wide_bytes = wide.memory_bytes();
            // What is left once the source is made (0 means no limit: none left is asked as 1 byte).
            const std::uint64_t left = wide_cfg.max_bytes == 0      ? 0
                                       : wide_bytes >= wide_cfg.max_bytes ? 1
                                                                          : wide_cfg.max_bytes - wide_bytes;
            layout_ = make_compact_layout<N>(std::move(wide), tris, left, &scratch_bytes);
            return WideShape{N, layout_.nodes.size(), layout_.leaves, layout_.memory_bytes()};
        });
        // The conversion holds the binary tree, the wide layout, the compact layout (less the
        // octant orders, moved from the wide one) and the lists that place its leaves at once (the
        // peak init worked out counts the compact layout only); with the converter's words, as init
        // counts them, so that the peak is what the limit was checked against.
        const std::size_t compact_bytes = stats_.memory_bytes - layout_.orders.capacity();
        stats_.build_peak_bytes = std::max(stats_.build_peak_bytes,
                                           conversion_held_bytes(bvh) + wide_bytes + scratch_bytes + compact_bytes);
        offer_.add(TracePath::single);
        offer_.add(TracePath::packet);
        offer_.packets_pay = true;
        offer_.packet_lanes = this->packets_.lanes;
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
                    layout_.for_blocks(first, n, [&](const CompactBlock& blk, std::uint32_t) {
                        const simd::TriHit<T> h = compact_triangles<T>(r, blk);
                        for (std::uint32_t bits = simd::to_bits(h.hit); bits != 0; bits &= bits - 1) {
                            const auto l = std::uint32_t(std::countr_zero(bits));
                            hits.push_back({simd::lane(h.t, l), blk.prim(l), simd::lane(h.u, l), simd::lane(h.v, l)});
                        }
                    });
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
                        if (node.count[c] == 0) continue;
                        layout_.for_blocks(node.child[c], node.count[c], [&](const CompactBlock& blk, std::uint32_t) {
                            for (std::uint32_t t = 0; t < blk.nb; ++t)
                                s.offer(blk.vertex(t, 0), blk.vertex(t, 1), blk.vertex(t, 2), blk.prim(t));
                        });
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
        CompactBlock blk = layout_.block(first, n);
        for (std::uint32_t b = 0;;) {
            const simd::TriHit<T> h = compact_triangles<T>(r, blk);
            const std::uint32_t bits = simd::to_bits(h.hit);
            if (bits != 0) {
                // The lowest lane among equal t: the lowest prim (the leaf is in ascending prim
                // order; the lanes past its end are NaN padding, which never hits).
                const int lane = AnyHit ? std::countr_zero(bits) : simd::closest_lane<T>(h.hit, h.t);
                const float t = simd::lane(h.t, std::size_t(lane));
                if (best.offer(t, blk.prim(std::uint32_t(lane)), simd::lane(h.u, std::size_t(lane)),
                               simd::lane(h.v, std::size_t(lane)))) {
                    tfar = t;
                    r.tfar = T(t);
                    found = true;
                    if constexpr (AnyHit) return true;
                }
            }
            b += blk.nb;
            if (b >= n) return found;
            blk = blk.next(std::min<std::uint32_t>(n - b, N));
        }
    }

    /// Ray `r` (traceable, far distance `tfar`) through the subtree (child, count) (Root false; the
    /// root is (0, 0)), or from the root whose test test_root (wide_root.h) has done (Root true:
    /// the root's other hit children `rest` with entry distances `root_t` deferred, and the first
    /// child's test `first_bits`, `first_t` when it is a node), as WideBvhAccel::walk_ray.
    template <bool AnyHit, bool Root = false>
    ARBOR_INLINE Hit walk_ray(simd::WideRay<T>& r, float tfar, WideStack& stack, std::uint32_t child = 0,
                              std::uint32_t count = 0, std::uint32_t rest = 0, const T& root_t = T(0.0f),
                              std::uint32_t first_bits = 0, const float* first_t = nullptr) const {
        HitRecord<AnyHit> best;
        // (Forced inline: as a call, the walk's WideRay lived in memory and every node test reloaded it.)
        const auto leaf = [&](std::uint32_t first, std::uint32_t n) __attribute__((always_inline)) {
            return test_leaf(r, tfar, best, first, n);
        };
        if (r.plain)
            detail::walk_wide<AnyHit, true, Root>(layout_, r, tfar, stack, child, count, rest, root_t, first_bits,
                                                  first_t, leaf);
        else
            detail::walk_wide<AnyHit, false, Root>(layout_, r, tfar, stack, child, count, rest, root_t, first_bits,
                                                   first_t, leaf);
        return best.hit;
    }

    /// The rays' set-up in groups, then each ray's walk; for a group whose rays go in different
    /// octants, the group's root tests first (wide_root.h), as WideBvhAccel::trace_single does.
    template <bool AnyHit>
    void trace_single(std::span<const Ray> rays, std::span<Hit> hits) const {
        if (layout_.empty()) {
            std::fill(hits.begin(), hits.end(), Hit{});
            return;
        }
        WideStack stack(layout_.stack_size());
        simd::WideRaySetup<simd::SetupLane> setup;
        RootTests<N, simd::WideRaySetup<simd::SetupLane>::size> root;
        simd::WideRay<T> r;
        for (std::size_t base = 0; base < rays.size(); base += setup.size) {
            const auto in = rays.subspan(base, std::min(setup.size, rays.size() - base));
            simd::wide_ray_setup(in, setup);
            if (!mixed_octants(setup)) {
                for (std::size_t i = 0; i < in.size(); ++i) {
                    setup.get(i, r);
                    hits[base + i] = r.traceable ? walk_ray<AnyHit>(r, in[i].tfar, stack) : Hit{};
                }
                continue;
            }
            trace_group<AnyHit>(in, hits.subspan(base, in.size()), setup, root, stack);
        }
    }

    /// trace_single's rays `in` of a group in different octants: their root tests, then their walks.
    template <bool AnyHit, class Setup, class Root>
    __attribute__((noinline)) void trace_group(std::span<const Ray> in, std::span<Hit> hits, const Setup& setup,
                                               Root& root, WideStack& stack) const {
        test_root(layout_, setup, in.size(), root);
        simd::WideRay<T> r;
        for (std::size_t i = 0; i < in.size(); ++i) {
            if (!root.live[i]) {  // (untraceable, or no root child left to visit)
                hits[i] = Hit{};
                continue;
            }
            setup.get(i, r);
            hits[i] = walk_ray<AnyHit, true>(r, in[i].tfar, stack, root.child[i], root.count[i], root.rest[i],
                                             root.entry(i), root.bits2[i], root.t2[i]);
        }
    }

    /// Packets of lanes<P> consecutive rays (the last one partial): WideBvhAccel's packet path
    /// (wide_paths_impl.h) on the compact layout. A leaf's blocks are gathered (compact_block)
    /// for all lanes at once, then tested as that path tests a WideBlock: the triangles' boxes
    /// against the packet's bounds, then each triangle left against the packet.
    template <bool AnyHit, class P>
    void trace_packets(std::span<const Ray> rays, std::span<Hit> hits) const {
        if (layout_.empty()) {
            std::fill(hits.begin(), hits.end(), Hit{});
            return;
        }
        constexpr std::size_t K = simd::lanes<P>;
        using IntP = simd::IntOf<P>;
        StackBuffer<PacketStackEntry<P>, 256> pstack(layout_.stack_size());
        WideStack sstack(layout_.stack_size());
        simd::WideRaySetup<P> setup;
        for (std::size_t base = 0; base < rays.size(); base += K) {
            const auto in = rays.subspan(base, std::min(K, rays.size() - base));
            simd::RayPacket<P> p = simd::load_packet_boxes<P>(in);
            const simd::Mask<P> loaded = p.active;
            bool have_woop = false;
            const auto need_woop = [&] {
                if (!have_woop) simd::add_woop(p, loaded), have_woop = true;
            };
            simd::PacketHit<P> best;
            const auto offer = [&](const simd::Mask<P>& candidates, const P& t, const IntP& prim, const P& u,
                                   const P& v) {
                const auto take = simd::offer_lanes<AnyHit>(best, candidates, t, prim, u, v);
                p.tfar = simd::select(take, t, p.tfar);
                return simd::to_bits(take);
            };
            const simd::PacketBounds bounds = simd::packet_bounds(p, p.active);
            auto leaf = [&](std::uint32_t first, std::uint32_t count, std::uint32_t lanes) {
                need_woop();
                auto live = simd::from_bits<P>(lanes);
                const float tfar_hi = -simd::hmin(simd::select(live, -p.tbox, P(INFINITY)));  // (box_tfar: ray_box.h)
                // (Locals, written back once: see WideBvhAccel::trace_packets.)
                P tfar = p.tfar;
                simd::PacketHit<P> rec = best;
                std::uint32_t found = 0;
                simd::TrisSoA<N> blk;
                CompactBlock at = layout_.block(first, count);
                for (std::uint32_t b = 0; b < count; b += N) {
                    if (b != 0) at = at.next(std::min<std::uint32_t>(count - b, N));
                    compact_block(at, blk);
                    const std::uint32_t used = at.nb;
                    std::uint32_t maybe = simd::to_bits(simd::bounds_triangles<T>(bounds, tfar_hi, &blk.v[0][0][0]));
                    maybe &= used == 32 ? ~0u : (1u << used) - 1u;
                    for (; maybe != 0; maybe &= maybe - 1) {
                        const int l = std::countr_zero(maybe);
                        const Vec3f v0{blk.v[0][0][l], blk.v[0][1][l], blk.v[0][2][l]};
                        const Vec3f v1{blk.v[1][0][l], blk.v[1][1][l], blk.v[1][2][l]};
                        const Vec3f v2{blk.v[2][0][l], blk.v[2][1][l], blk.v[2][2][l]};
                        const simd::TriHit<P> h = simd::packet_triangle(p, tfar, v0, v1, v2);
                        const auto take = simd::offer_lanes<AnyHit>(
                            rec, h.hit & live, h.t, IntP(std::int32_t(at.prim(std::uint32_t(l)))), h.u, h.v);
                        const std::uint32_t bits = simd::to_bits(take);
                        if (bits == 0) continue;
                        tfar = simd::select(take, h.t, tfar);
                        found |= bits;
                        if constexpr (AnyHit) {
                            live = live & !take;
                            if (simd::none(live)) break;
                        }
                    }
                    if (AnyHit && simd::none(live)) break;
                }
                if (found != 0) {
                    p.tfar = tfar;
                    best = rec;
                }
                return found;
            };
            bool have_setup = false;
            auto single = [&](int i, std::uint32_t child, std::uint32_t count) {
                if (!have_setup) {
                    need_woop();
                    simd::wide_ray_setup(p, setup);
                    have_setup = true;
                }
                const float tfar = simd::lane(p.tfar, std::size_t(i));
                simd::WideRay<T> r;
                setup.get(std::size_t(i), r);
                r.tfar = T(tfar);
                r.tbox = T(simd::box_tfar(tfar));
                const Hit h = walk_ray<AnyHit>(r, tfar, sstack, child, count);
                if (!h.is_hit()) return false;
                return offer(simd::from_bits<P>(1u << i), P(h.t), IntP(std::int32_t(h.prim)), P(h.u), P(h.v)) != 0;
            };
            const int octant = packet_octant(p);
            traverse_packet<AnyHit>(layout_, p, bounds, pstack.data(),
                                    octant >= 0 ? this->packets_.switch_lanes : this->packets_.switch_mixed, octant,
                                    leaf, single);
            simd::store_hits(best, hits.subspan(base, in.size()));
        }
    }

    void run(std::span<const Ray> rays, std::span<Hit> hits, Query query, TracePath path,
             TraceCounters* counters) const override {
        if (counters)
            return BvhAccel::run(rays, hits, query, TracePath::scalar, counters);  // (check_counts threw before)
        this->trace_simd(rays, hits, query, path);
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
