#pragma once
/// WideBvhAccel<N>: a BVH with its N-wide SIMD layout (and, when built, its scalar layout), and the
/// batch loops of the SIMD paths for that width. Included only by the wide_paths{4,8,16}.cpp
/// files, which instantiate one width each (compile time, and each width in its own translation
/// unit).
#include "accel/structures/bvh_accel.h"
#include "accel/core/hit_record.h"
#include "accel/core/simd_paths.h"
#include "accel/util/stack_buffer.h"
#include "accel/wide/wide_counts.h"
#include "accel/wide/wide_packet.h"
#include "accel/structures/wide_paths.h"
#include "accel/wide/wide_queries.h"
#include "accel/wide/wide_refit.h"
#include "accel/wide/wide_root.h"
#include "accel/wide/wide_shared_leaves.h"
#include "accel/wide/wide_traverse.h"
#include "accel/wide/wide_winding.h"
#include "simd/packet_bounds.h"
#include "simd/tri_kernels.h"
#include "simd/wide_ray_setup.h"

#include <algorithm>
#include <array>
#include <vector>

namespace arbor::accel {

template <std::size_t N> class WideBvhAccel final : public BvhAccel, public SimdPaths<WideBvhAccel<N>> {
    friend class SimdPaths<WideBvhAccel<N>>;

public:
    using T = WideLane<N>;

    WideBvhAccel(AccelKind kind, const BinaryBvh& bvh, const TriangleView& tris, const BuildConfig& cfg, double build_ms)
        : BvhAccel(kind), SimdPaths<WideBvhAccel<N>>(resolve_packets(cfg.packets)) {
        init(bvh, tris, cfg, build_ms, [&](const WideConfig& wide) {
            layout_ = make_wide_layout<N>(bvh, tris, wide);
            return WideShape{N, layout_.nodes.size(), layout_.leaves, layout_.memory_bytes()};
        });
        // (Not for the kd-tree's cell layout, KdCellAccel: on its cells the pass lost, builtin:default
        // random and diffuse 0.95-0.97x of it off, 1 thread, in one process.)
        shared_leaf_triangles_ = cfg.wide.shared_leaf_triangles;
        if (kind != AccelKind::kdtree)
            shared_slots_ = shared_leaf_slots(layout_, shared_leaf_triangles_, simd::WideRaySetup<simd::SetupLane>::size);
        if (!layout_.empty()) built_sah_ = wide_sah_cost(layout_);
        offer_.add(TracePath::single);
        offer_.add(TracePath::packet);
        offer_.packets_pay = true;
        offer_.packet_lanes = this->packets_.lanes;
    }

    const WideLayout<N>& wide_layout() const { return layout_; }

    /// Dipoles on the SIMD layout (wide/wide_winding.h), whether or not the scalar one was built too.
    std::unique_ptr<WindingTree> make_winding_tree(const TriangleView&) const override {
        return make_wide_winding<N>(layout_);
    }

    /// On the SIMD layout (wide_queries.h), whether or not the scalar one was built too.
    void trace_all(std::span<const Ray> rays, HitSink& sink) const override {
        WideStack stack(layout_.stack_size());
        std::vector<Hit> hits;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            hits.clear();
            all_hits_wide<N>(layout_, rays[i], stack, hits);
            sort_unique_hits(hits);
            sink.take(i, hits);
        }
    }

    void closest_points(std::span<const Vec3f> points, float max_distance, std::span<PointHit> out) const override {
        std::vector<PointStackEntry> stack;
        for (std::size_t i = 0; i < points.size(); ++i) {
            PointSearch s(points[i], i == 0 ? max_distance : warm_reach(points[i], out[i - 1], max_distance));
            closest_point_wide<N>(layout_, s, stack);
            out[i] = s.result();
        }
    }

    /// Ray `r` (traceable, far distance `tfar`) through the subtree (child, count).
    template <bool AnyHit>
    Hit trace_from(simd::WideRay<T>& r, float tfar, std::uint32_t child, std::uint32_t count, WideStack& stack) const {
        return walk_ray<AnyHit, false>(r, tfar, child, count, 0, T(0.0f), 0, nullptr, Hit{}, stack);
    }

    /// Ray `r` (traceable, far distance `tfar`) from the root, whose test test_root (wide_root.h)
    /// has done: ray i of `root` (root.live[i] set).
    template <bool AnyHit, std::size_t Rays>
    Hit trace_root(simd::WideRay<T>& r, float tfar, const RootTests<N, Rays>& root, std::size_t i, WideStack& stack) const {
        return walk_ray<AnyHit, true>(r, tfar, root.child[i], root.count[i], root.rest[i], root.entry(i), root.bits2[i],
                                      root.t2[i], Hit{}, stack);
    }

    /// The counted single-ray walk: each ray as trace_single walks it, from the root with the root
    /// test inside the walk (the nodes and leaves, in the same order, that the walks after a group's
    /// root test visit too, wide_root.h; the shared root leaves of trace_group_shared are not used),
    /// its hit into `hits` (bit for bit TracePath::single's) and what the walks did added to
    /// `counts`. Not a timed path: the counters live in their own instantiation of the walk and
    /// the leaf test.
    void trace_counted(std::span<const Ray> rays, std::span<Hit> hits, Query query, WideCounts& counts) const {
        if (query == Query::any)
            count_rays<true>(rays, hits, counts);
        else
            count_rays<false>(rays, hits, counts);
    }

protected:
    /// The scalar layout (when built) and the SIMD layout; what depends on the boxes is worked out
    /// again as the build does it: the shared root leaves (and, in refit(), the scene's diagonal).
    double refit_layouts(const TriangleView& tris, Bounds& bounds) override {
        const double scalar = BvhAccel::refit_layouts(tris, bounds);
        if (layout_.empty()) return scalar;
        const double cost = refit_wide_layout(layout_, tris);
        if (kind_ != AccelKind::kdtree)
            shared_slots_ = shared_leaf_slots(layout_, shared_leaf_triangles_, simd::WideRaySetup<simd::SetupLane>::size);
        bounds = Bounds{};
        for (std::size_t c = 0; c < layout_.nodes[0].children; ++c)
            bounds.grow(Bounds{layout_.nodes[0].boxes.lo(c), layout_.nodes[0].boxes.hi(c)});
        return cost;
    }

private:
    /// The leaf of the single walk: ray `r`'s test of the leaf (first block, n triangles), its hits
    /// offered to `best`; a kept hit lowers `tfar` and r.tfar (and ends the leaf for AnyHit). True
    /// when one was kept. Count: the blocks tested and their triangles added to `*counts`.
    template <bool AnyHit, bool Count = false>
    ARBOR_INLINE bool test_leaf(simd::WideRay<T>& r, float& tfar, HitRecord<AnyHit>& best, std::uint32_t first,
                                std::uint32_t n, WideCounts* counts = nullptr) const {
        const WideBlock<N>* blocks = layout_.blocks.data();
        bool found = false;
        const std::uint32_t end = first + wide_blocks<N>(n);
        for (std::uint32_t b = first; b < end; ++b) {
            if constexpr (Count)
                counts->blocks += 1, counts->triangles += std::min<std::uint32_t>(N, n - (b - first) * N);
            // (Early out: a block no lane of which can hit skips the division, +5% on random rays.)
            const simd::TriHit<T> h = simd::ray_triangles<T, true>(r, blocks[b].soa());
            const std::uint32_t bits = simd::to_bits(h.hit);
            if (bits == 0) continue;
            // Closest: the smallest t, on equal t the lowest lane, which is the lowest prim (a
            // leaf's triangles are in ascending prim order, wide_layout.h).
            const int lane = AnyHit ? std::countr_zero(bits) : simd::closest_lane<T>(h.hit, h.t);
            const float t = simd::lane(h.t, std::size_t(lane));
            if (!best.offer(t, blocks[b].ids[lane], simd::lane(h.u, std::size_t(lane)), simd::lane(h.v, std::size_t(lane))))
                continue;
            tfar = t;
            r.tfar = T(t);
            found = true;
            if constexpr (AnyHit) return true;
        }
        return found;
    }

    /// The walk of trace_from (Root false: from (child, count)) and trace_root (Root true: from
    /// (child, count) with the root's children `rest`, entry distances `root_t`, deferred), with
    /// the hit record and the leaf test. Forced inline into trace_single: as a call (the walk's
    /// WideRay then in memory, not in registers), cheap rays such as the flat models' shadow rays
    /// took 1.3x as long. `start`: the record's first hit (a miss, or a closest hit found before
    /// the walk, test_shared_leaves; `tfar` and r.tfar are then its t).
    template <bool AnyHit, bool Root>
    ARBOR_INLINE Hit walk_ray(simd::WideRay<T>& r, float tfar, std::uint32_t child, std::uint32_t count, std::uint32_t rest,
                              const T& root_t, std::uint32_t first_bits, const float* first_t, const Hit& start,
                              WideStack& stack) const {
        HitRecord<AnyHit> best{start};
        // The leaf test (test_leaf): forced inline into the walks from a group's root tests
        // (trace_group, rays of mixed directions), where GCC 12 kept it a call from both walks of
        // walk_ray (random rays 1.02-1.09x inlined); elsewhere GCC's choice, a call as before
        // (forced there too, shadow rays' any-hit walks took 1.1x as long).
        if constexpr (Root) {
            const auto leaf = [&](std::uint32_t first, std::uint32_t n)
                                  __attribute__((always_inline)) { return test_leaf(r, tfar, best, first, n); };
            if (r.plain) detail::walk_wide<AnyHit, true, Root>(layout_, r, tfar, stack, child, count, rest, root_t, first_bits, first_t, leaf);
            else detail::walk_wide<AnyHit, false, Root>(layout_, r, tfar, stack, child, count, rest, root_t, first_bits, first_t, leaf);
        } else {
            const auto leaf = [&](std::uint32_t first, std::uint32_t n) { return test_leaf(r, tfar, best, first, n); };
            if (r.plain) detail::walk_wide<AnyHit, true, Root>(layout_, r, tfar, stack, child, count, rest, root_t, first_bits, first_t, leaf);
            else detail::walk_wide<AnyHit, false, Root>(layout_, r, tfar, stack, child, count, rest, root_t, first_bits, first_t, leaf);
        }
        return best.hit;
    }

    /// trace_counted's rays, set up in groups as trace_single sets them up.
    template <bool AnyHit>
    void count_rays(std::span<const Ray> rays, std::span<Hit> hits, WideCounts& counts) const {
        counts.rays += rays.size();
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
                if (!r.traceable) {
                    hits[base + i] = Hit{};
                    continue;
                }
                float tfar = in[i].tfar;
                HitRecord<AnyHit> best{Hit{}};
                const auto leaf = [&](std::uint32_t first, std::uint32_t n) {
                    return test_leaf<AnyHit, true>(r, tfar, best, first, n, &counts);
                };
                if (r.plain)
                    detail::walk_wide<AnyHit, true, false, true>(layout_, r, tfar, stack, 0, 0, 0, T(0.0f), 0, nullptr,
                                                                 leaf, &counts.node_tests);
                else
                    detail::walk_wide<AnyHit, false, false, true>(layout_, r, tfar, stack, 0, 0, 0, T(0.0f), 0, nullptr,
                                                                  leaf, &counts.node_tests);
                hits[base + i] = best.hit;
            }
        }
    }

    void run(std::span<const Ray> rays, std::span<Hit> hits, Query query, TracePath path,
             TraceCounters* counters) const override {
        if (counters || path == TracePath::scalar) return run_scalar(rays, hits, query, counters);
        this->trace_simd(rays, hits, query, path);
    }

    /// The rays' set-up in groups (simd/wide_ray_setup.h), then each ray's walk. For a group whose
    /// rays go in different octants (incoherent rays), the group's root tests first (wide_root.h),
    /// each ray's walk then on from its root test: on random rays the root's outcome differs from
    /// ray to ray, and tested inside each walk its branches were mispredicted one ray after the
    /// other. For a group in one octant (camera and shadow rays), the root test inside the walk,
    /// well predicted there, costs less than the separate pass (1 thread, flat models' shadow
    /// rays: 0.67-0.82x with the pass).
    template <bool AnyHit> void trace_single(std::span<const Ray> rays, std::span<Hit> hits) const {
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
                    hits[base + i] = r.traceable ? walk_ray<AnyHit, false>(r, in[i].tfar, 0, 0, 0, T(0.0f), 0, nullptr, Hit{}, stack) : Hit{};
                }
                continue;
            }
            if constexpr (!AnyHit)
                if (shared_slots_ != 0) {
                    trace_group_shared(in, hits.subspan(base, in.size()), setup, root, stack);
                    continue;
                }
            trace_group<AnyHit, false>(in, hits.subspan(base, in.size()), setup, root, stack, nullptr, nullptr);
        }
    }

    /// trace_single's rays `in` of a group in different octants (set up in `setup`): their root
    /// tests, then their walks. Shared: after test_shared_leaves (trace_group_shared), which left
    /// the root leaves it tested for each ray in `skip` and its hits in `shared`. (A call of its
    /// own: inlined, it made the one-octant rays' loop of trace_single 1.03-1.05x slower on camera
    /// rays.)
    template <bool AnyHit, bool Shared, class Setup, class Root>
    __attribute__((noinline)) void trace_group(std::span<const Ray> in, std::span<Hit> hits, const Setup& setup, Root& root,
                                               WideStack& stack, const std::uint32_t* skip,
                                               const SharedHits<Setup::size>* shared) const {
        test_root<Shared>(layout_, setup, in.size(), root, skip);
        simd::WideRay<T> r;
        for (std::size_t i = 0; i < in.size(); ++i) {
            const Hit start = Shared ? shared->hit(i) : Hit{};
            if (!root.live[i]) {  // (untraceable, or no root child left to visit)
                hits[i] = start;
                continue;
            }
            setup.get(i, r);
            // (The far distance of the set-up: the ray's own, or its hit in the shared leaves.)
            hits[i] = walk_ray<AnyHit, true>(r, Shared ? setup.f[Setup::tfar][i] : in[i].tfar, root.child[i], root.count[i],
                                             root.rest[i], root.entry(i), root.bits2[i], root.t2[i], start, stack);
        }
    }

    /// trace_group for closest hits on a layout with small root leaves (shared_slots_): those
    /// that many of the group's rays hit tested for the group at once first (wide_shared_leaves.h).
    /// (Its own call, so that trace_single stays as it was for the other layouts.)
    template <class Setup, class Root>
    __attribute__((noinline)) void trace_group_shared(std::span<const Ray> in, std::span<Hit> hits, Setup& setup, Root& root,
                                                      WideStack& stack) const {
        std::uint32_t skip[Setup::size];
        SharedHits<Setup::size> shared;
        if (test_shared_leaves(layout_, shared_slots_, in, setup, skip, shared))
            trace_group<false, true>(in, hits, setup, root, stack, skip, &shared);
        else
            trace_group<false, false>(in, hits, setup, root, stack, nullptr, nullptr);
    }

    /// Packets of lanes<P> consecutive rays (the last one partial), see wide_packet.h.
    template <bool AnyHit, class P> void trace_packets(std::span<const Ray> rays, std::span<Hit> hits) const {
        if (layout_.empty()) {
            std::fill(hits.begin(), hits.end(), Hit{});
            return;
        }
        constexpr std::size_t K = simd::lanes<P>;
        using IntP = simd::IntOf<P>;
        StackBuffer<PacketStackEntry<P>, 256> pstack(layout_.stack_size());
        WideStack sstack(layout_.stack_size());
        const WideBlock<N>* blocks = layout_.blocks.data();
        simd::WideRaySetup<P> setup;
        for (std::size_t base = 0; base < rays.size(); base += K) {
            const auto in = rays.subspan(base, std::min(K, rays.size() - base));
            // The triangle test's set-up (p.woop) only once a lane reaches a leaf (make_packet<P, false>).
            simd::RayPacket<P> p = simd::load_packet_boxes<P>(in);
            const simd::Mask<P> loaded = p.active;
            bool have_woop = false;
            const auto need_woop = [&] {
                if (!have_woop) simd::add_woop(p, loaded), have_woop = true;
            };
            simd::PacketHit<P> best;
            // The hit record of the packet's lanes (simd::offer_lanes: the rule of HitRecord).
            const auto offer = [&](const simd::Mask<P>& candidates, const P& t, const IntP& prim, const P& u, const P& v) {
                const auto take = simd::offer_lanes<AnyHit>(best, candidates, t, prim, u, v);
                p.tfar = simd::select(take, t, p.tfar);
                return simd::to_bits(take);
            };
            const simd::PacketBounds bounds = simd::packet_bounds(p, p.active);
            auto leaf = [&](std::uint32_t first, std::uint32_t count, std::uint32_t lanes) {
                need_woop();
                auto live = simd::from_bits<P>(lanes);
                const float tfar_hi = -simd::hmin(simd::select(live, -p.tbox, P(INFINITY)));  // (box_tfar: ray_box.h)
                // The far distances and the hit record in locals for the leaf's tests (as members
                // of p and best, reached through the lambdas' references, each test stored them
                // with a masked store and the next test loaded them back: a store-forwarding stall
                // per triangle); written back once at the end.
                P tfar = p.tfar;
                simd::PacketHit<P> rec = best;
                std::uint32_t found = 0;
                for (std::uint32_t b = 0; b < wide_blocks<N>(count); ++b) {
                    const simd::TrisSoA<N>& blk = blocks[first + b].tris;
                    // The triangles' boxes against the packet's bounds first: most triangles of a
                    // leaf lie outside a coherent packet.
                    const std::uint32_t used = std::min<std::uint32_t>(count - b * N, N);
                    std::uint32_t maybe = simd::to_bits(simd::bounds_triangles<T>(bounds, tfar_hi, &blk.v[0][0][0]));
                    maybe &= used == 32 ? ~0u : (1u << used) - 1u;
                    for (; maybe != 0; maybe &= maybe - 1) {
                        const int l = std::countr_zero(maybe);
                        const Vec3f v0{blk.v[0][0][l], blk.v[0][1][l], blk.v[0][2][l]};
                        const Vec3f v1{blk.v[1][0][l], blk.v[1][1][l], blk.v[1][2][l]};
                        const Vec3f v2{blk.v[2][0][l], blk.v[2][1][l], blk.v[2][2][l]};
                        const simd::TriHit<P> h = simd::packet_triangle(p, tfar, v0, v1, v2);
                        const auto take = simd::offer_lanes<AnyHit>(rec, h.hit & live, h.t,
                                                                    IntP(std::int32_t(blocks[first + b].ids[l])), h.u, h.v);
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
                if (found != 0) {  // (nothing taken: both as they were)
                    p.tfar = tfar;
                    best = rec;
                }
                return found;
            };
            bool have_setup = false;
            auto single = [&](int i, std::uint32_t child, std::uint32_t count) {
                // The lanes' WideRays from the packet itself, worked out once per packet (a lane's
                // far distance only drops, to a hit's t >= tnear, so the rest stays as it was).
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
                const Hit h = trace_from<AnyHit>(r, tfar, child, count, sstack);
                if (!h.is_hit()) return false;
                return offer(simd::from_bits<P>(1u << i), P(h.t), IntP(std::int32_t(h.prim)), P(h.u), P(h.v)) != 0;
            };
            const int octant = packet_octant(p);
            traverse_packet<AnyHit>(layout_, p, bounds, pstack.data(),
                                    octant >= 0 ? this->packets_.switch_lanes : this->packets_.switch_mixed,
                                    octant, leaf, single);
            simd::store_hits(best, hits.subspan(base, in.size()));
        }
    }

    WideLayout<N> layout_;
    std::uint32_t shared_slots_ = 0;  ///< shared_leaf_slots(layout_)
    std::uint32_t shared_leaf_triangles_ = 0;  ///< WideConfig::shared_leaf_triangles of the build
};

/// The BVH of width N (defined in wide_paths{N}.cpp).
template <std::size_t N>
std::unique_ptr<Accel> make_wide_bvh_accel_n(AccelKind kind, const BinaryBvh& bvh, const TriangleView& tris,
                                             const BuildConfig& cfg, double build_ms);

}  // namespace arbor::accel
