// The kd-tree's SIMD paths (kdtree_simd.h).
//
// single: the scalar walks with each leaf's triangles tested as SIMD blocks by one WideRay
// (simd::ray_triangles, the watertight test of ray_triangle.h on N triangles at once): the rope walk
// (kd::walk_ropes) for closest hit, the front-to-back stack walk (kd::walk_stack) for any hit.
//
// packet: the lanes of a packet whose directions share an octant (at least half the packet) walk
// the nodes together (kd::walk_stack_packet, Wald 2004), each lane taking exactly the decisions of
// its own scalar stack walk, so it meets exactly that walk's leaves in the same order: any-hit
// answers are the scalar path's (which walks the stack for any hit), closest-hit answers are the
// closest hit, as the ropes find it. At a leaf the lanes that reach it are tested lane by lane
// with the single path's block test, or, when enough of them reach it and that is fewer tests,
// one triangle against all of them (simd::packet_triangle) after the triangles' boxes are culled
// against the group's interval bounds. The other lanes (mixed-octant packets: diffuse bounces)
// take the single path's walk, ray by ray.
#include "accel/structures/kdtree_simd.h"

#include "accel/core/hit_record.h"
#include "accel/core/simd_paths.h"
#include "accel/kdtree/kdtree_blocks.h"
#include "accel/kdtree/kdtree_stack_packet.h"
#include "accel/kdtree/kdtree_traverse.h"
#include "simd/packet_bounds.h"
#include "simd/tri_kernels.h"
#include "simd/wide_ray.h"
#include "accel/util/timer.h"

#include <algorithm>
#include <bit>

namespace arbor::accel::kset {
namespace {

template <std::size_t N> struct LaneOf;
template <> struct LaneOf<4> { using type = simd::Float4; };
#if XSIMD_WITH_AVX2
template <> struct LaneOf<8> { using type = simd::Float8; };
#endif
#if XSIMD_WITH_AVX512F
template <> struct LaneOf<16> { using type = simd::Float16; };
#endif

template <std::size_t N> class KdSimdAccel final : public KdTreeAccel, public SimdPaths<KdSimdAccel<N>> {
    friend class SimdPaths<KdSimdAccel<N>>;

public:
    using T = typename LaneOf<N>::type;

    KdSimdAccel(KdTree&& tree, const BuildConfig& cfg, double build_ms)
        : KdTreeAccel(std::move(tree), cfg, build_ms), SimdPaths<KdSimdAccel<N>>(resolve_packets(cfg.packets)) {
        const Timer timer;
        blocks_ = make_kd_blocks<N>(tree_);
        stats_.build_ms += timer.ms();
        stats_.memory_bytes += blocks_.memory_bytes();
        offer_.add(TracePath::single);
        offer_.add(TracePath::packet);
        offer_.simd_skipped = false;
        block_width_ = N;
        offer_.packet_lanes = this->packets_.lanes;
        // The packet walk (kdtree_stack_packet.h) runs 1.3-1.7x the single path on coherent primary
        // and shadow rays; mixed-octant packets go ray by ray.
        offer_.packets_pay = true;
    }

private:
    void run(std::span<const Ray> rays, std::span<Hit> hits, Query query, TracePath path,
             TraceCounters* counters) const override {
        if (counters || path == TracePath::scalar) return run_scalar(rays, hits, query, counters);
        this->trace_simd(rays, hits, query, path);
    }

    template <bool AnyHit> void trace_single(std::span<const Ray> rays, std::span<Hit> hits) const {
        for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = trace_lane<AnyHit>(rays[i]);
    }

    /// The triangles of leaf `li` against ray `r` (r.tfar: the current best distance or the ray's
    /// tfar), offered to `best`. Returns true (any hit) when a hit was found.
    template <bool AnyHit> bool test_leaf(simd::WideRay<T>& r, std::uint32_t li, HitRecord<AnyHit>& best) const {
        const KdBlock<N>* b = blocks_.blocks.data() + blocks_.first[li];
        const KdBlock<N>* end = blocks_.blocks.data() + blocks_.first[li + 1];
        for (; b != end; ++b) {
            const simd::TriHit<T> h = simd::ray_triangles<T>(r, &b->tris.v[0][0][0]);
            const std::uint32_t bits = simd::to_bits(h.hit);
            if (bits == 0) continue;
            // Any hit: the first triangle of the leaf that hits; closest: the smallest t, on equal t
            // the lowest lane, which is the lowest prim (a leaf's triangles are in ascending prim order).
            const int lane = AnyHit ? std::countr_zero(bits) : simd::closest_lane<T>(h.hit, h.t);
            const float t = simd::lane(h.t, std::size_t(lane));
            if (!best.offer(t, b->ids[lane], simd::lane(h.u, std::size_t(lane)), simd::lane(h.v, std::size_t(lane)))) continue;
            if constexpr (AnyHit) return true;
            r.tfar = T(t);
        }
        return false;
    }

    template <bool AnyHit> Hit trace_lane(const Ray& ray) const {
        const KdTree& tree = tree_;
        HitRecord<AnyHit> best;
        if (tree.empty() || !ray_is_traceable(ray)) return best.hit;
        std::uint64_t visited = 0;
        simd::WideRay<T> r;
        const auto leaf_fn = [&](std::uint32_t li) { return test_leaf<AnyHit>(r, li, best); };
        if constexpr (AnyHit) {
            r = simd::wide_ray<T>(ray.org, ray.dir, ray.tnear, ray.tfar);
            kd::walk_stack<true>(tree, ray, best.hit.t, leaf_fn, visited);
        } else {
            // The wide ray only for rays that meet the scene box: many diffuse rays leaving the
            // alligator and woody do not, and spent ~40% of their time making it (perf record).
            kd::RopeRay s;
            double t0 = 0.0;
            const kd::RopeStart start = kd::rope_start(tree, ray, s, t0);
            if (start == kd::RopeStart::none) return best.hit;
            r = simd::wide_ray<T>(ray.org, ray.dir, ray.tnear, ray.tfar);
            kd::walk_ropes_from<false>(tree, s, t0, start, best.hit.t, leaf_fn, visited);
        }
        return best.hit;
    }

    /// A packet's per-lane records while its lanes walk: the best hit so far and the far distance
    /// (the hit's t once there is one), in arrays the packet kernels load and store.
    template <std::size_t K> struct LaneRecords {
        alignas(64) float t[K], u[K], v[K], tfar[K];
        alignas(64) std::int32_t prim[K];
        simd::WideRay<T> wide[K];   ///< lane i's single-path ray, made when first needed
        std::uint32_t have_wide = 0;
        void reset() {
            for (std::size_t i = 0; i < K; ++i) t[i] = INFINITY, u[i] = v[i] = 0.0f, prim[i] = -1;
            have_wide = 0;
        }
        Hit hit(std::size_t i) const { return {t[i], std::uint32_t(prim[i]), u[i], v[i]}; }
    };

    /// Lane i of a packet alone against leaf li (the single path's block test), in the packet's
    /// records. Returns true (any hit) when the lane is done.
    template <bool AnyHit, std::size_t K>
    bool leaf_one_lane(const Ray& ray, int i, std::uint32_t li, LaneRecords<K>& rec) const {
        if (!(rec.have_wide >> i & 1u)) {
            rec.wide[i] = simd::wide_ray<T>(ray.org, ray.dir, ray.tnear, ray.tfar);
            rec.have_wide |= 1u << i;
        }
        simd::WideRay<T>& r = rec.wide[i];
        r.tfar = T(rec.tfar[i]);
        HitRecord<AnyHit> best{rec.hit(std::size_t(i))};
        const bool stop = test_leaf<AnyHit>(r, li, best);
        const Hit& h = best.hit;
        rec.t[i] = h.t, rec.prim[i] = std::int32_t(h.prim), rec.u[i] = h.u, rec.v[i] = h.v;
        if (h.is_hit()) rec.tfar[i] = h.t;
        return stop;
    }

    /// Leaf li for the lanes `group` of packet p at once, one triangle against all of them after
    /// the triangles' boxes are culled against the group's bounds; returns the lanes that are done
    /// (any hit). The far distances and the hit record stay in registers while the leaf is tested
    /// and are written back once, as the BVH packet leaf does.
    template <bool AnyHit, class P, std::size_t K>
    std::uint32_t leaf_together(const simd::RayPacket<P>& p, const simd::PacketBounds& bounds, std::uint32_t group,
                                std::uint32_t li, LaneRecords<K>& rec) const {
        using IntP = simd::IntOf<P>;
        auto live = simd::from_bits<P>(group);
        P far = simd::load_lanes<P>(rec.tfar);
        simd::PacketHit<P> best{simd::load_lanes<P>(rec.t), simd::load_lanes<P>(rec.u), simd::load_lanes<P>(rec.v),
                                simd::load_lanes<IntP>(rec.prim)};
        // The triangles' boxes culled against box_tfar of the far distances (ray_box.h: room for a
        // triangle's t rounded below its box's entry, as at a vertex the box's corner).
        const float tfar_hi = simd::box_tfar(-simd::hmin(simd::select(live, -far, P(INFINITY))));
        const std::uint32_t count = tree_.leaves[li].count;
        std::uint32_t done = 0;
        for (std::uint32_t b = blocks_.first[li], j = 0; b < blocks_.first[li + 1]; ++b, ++j) {
            const KdBlock<N>& blk = blocks_.blocks[b];
            const std::uint32_t used = std::min<std::uint32_t>(count - j * N, N);
            std::uint32_t maybe = simd::to_bits(simd::bounds_triangles<T>(bounds, tfar_hi, &blk.tris.v[0][0][0]));
            maybe &= used >= 32 ? ~0u : (1u << used) - 1u;
            for (; maybe != 0; maybe &= maybe - 1) {
                const int l = std::countr_zero(maybe);
                const auto& v = blk.tris.v;
                const simd::TriHit<P> h = simd::packet_triangle(p, far, Vec3f{v[0][0][l], v[0][1][l], v[0][2][l]},
                                                                Vec3f{v[1][0][l], v[1][1][l], v[1][2][l]},
                                                                Vec3f{v[2][0][l], v[2][1][l], v[2][2][l]});
                const auto take = simd::offer_lanes<AnyHit>(best, h.hit & live, h.t, IntP(std::int32_t(blk.ids[l])), h.u, h.v);
                const std::uint32_t bits = simd::to_bits(take);
                if (bits == 0) continue;
                far = simd::select(take, h.t, far);
                if constexpr (AnyHit) {
                    done |= bits;
                    live = live & !take;
                    if (simd::none(live)) break;
                }
            }
            if (AnyHit && simd::none(live)) break;
        }
        simd::store_lanes(best.t, rec.t);
        simd::store_lanes(best.u, rec.u);
        simd::store_lanes(best.v, rec.v);
        simd::store_lanes(best.prim, rec.prim);
        simd::store_lanes(far, rec.tfar);
        return done;
    }

    template <bool AnyHit, class P> void trace_packets(std::span<const Ray> rays, std::span<Hit> hits) const {
        const KdTree& tree = tree_;
        if (tree.empty()) {
            std::fill(hits.begin(), hits.end(), Hit{});
            return;
        }
        constexpr std::size_t K = simd::lanes<P>;
        kd::PacketStack<K> walk;
        LaneRecords<K> rec;
        for (std::size_t base = 0; base < rays.size(); base += K) {
            const auto in = rays.subspan(base, std::min(K, rays.size() - base));
            // The rays as loaded; the packet's triangle-test setup (make_packet) only once some
            // group of lanes meets the scene box (~10% of the path on alligator primary rays).
            const simd::PacketRays<P> raw = simd::load_rays<P>(in);
            const auto traceable = raw.active & simd::traceable(raw.org, raw.dir, raw.tnear, raw.tfar);
            simd::select(traceable, raw.tfar, P(-INFINITY)).store_aligned(rec.tfar);  // make_packet's p.tfar
            simd::RayPacket<P> p;
            bool have_packet = false;
            rec.reset();
            simd::PacketBounds bounds;
            // A leaf for the lanes `group` of a packet walk: together when at least switch_lanes + 1
            // lanes reach it and that is fewer triangle tests than their block tests; else lane by lane.
            const auto leaf = [&](std::uint32_t li, std::uint32_t group) -> std::uint32_t {
                const std::uint32_t nblocks = blocks_.first[li + 1] - blocks_.first[li];
                if (nblocks == 0) return 0;
                const int n = std::popcount(group);
                if (n > this->packets_.switch_lanes && std::uint32_t(n) * nblocks * 2 > tree.leaves[li].count)
                    return leaf_together<AnyHit>(p, bounds, group, li, rec);
                std::uint32_t done = 0;
                for (std::uint32_t l = group; l != 0; l &= l - 1) {
                    const int i = std::countr_zero(l);
                    if (leaf_one_lane<AnyHit>(in[std::size_t(i)], i, li, rec)) done |= 1u << i;
                }
                return done;
            };
            // Lanes grouped by the signs of their direction (inactive lanes: not traceable or past
            // the end), each group's lanes started at once (PacketStack::start, stack_start's state).
            const std::uint32_t active = simd::to_bits(traceable);
            const std::uint32_t sign[3] = {simd::to_bits(simd::signbit_mask(raw.dir.x)),
                                           simd::to_bits(simd::signbit_mask(raw.dir.y)),
                                           simd::to_bits(simd::signbit_mask(raw.dir.z))};
            alignas(64) float org[3][K], dir[3][K], tnear[K];
            for (int k = 0; k < 3; ++k) {
                raw.org[k].store_aligned(org[k]);
                raw.dir[k].store_aligned(dir[k]);
            }
            raw.tnear.store_aligned(tnear);
            std::uint32_t alone = 0;  // lanes of small groups: the single path's walk, ray by ray
            for (unsigned oct = 0; oct < 8; ++oct) {
                std::uint32_t group = active;
                for (int k = 0; k < 3; ++k) group &= (oct >> k & 1u) ? sign[k] : ~sign[k];
                if (group == 0) continue;
                if (std::popcount(group) < together_min(K)) {
                    alone |= group;
                    continue;
                }
                for (int k = 0; k < 3; ++k) walk.neg[k] = (oct >> k) & 1u;
                const std::uint32_t live = walk.template start<P>(tree, org, dir, tnear, rec.tfar, group);
                if (live == 0) continue;
                if (!have_packet) p = simd::make_packet<P>(raw.org, raw.dir, raw.tnear, raw.tfar, raw.active), have_packet = true;
                bounds = simd::packet_bounds(p, simd::from_bits<P>(live));
                kd::walk_stack_packet<AnyHit, P>(tree, walk, live, rec.t, leaf);
            }
            for (std::size_t i = 0; i < in.size(); ++i)
                hits[base + i] = (alone >> i & 1u) ? trace_lane<AnyHit>(in[i]) : rec.hit(i);
        }
    }

    /// Lanes of one direction octant that walk a packet's nodes together (fewer: ray by ray).
    /// Tuning rays, 1 thread (packet path, bunny and beast): half the lanes 1.0-1.2x a quarter on
    /// primary and shadow rays, and diffuse packets (mixed octants) then go ray by ray at 0.95-1.0x
    /// the single path instead of 0.75x.
    static constexpr int together_min(std::size_t lanes) { return int(lanes / 2); }

    KdBlocks<N> blocks_;
};

}  // namespace

std::uint32_t default_kd_block_width() { return XSIMD_WITH_AVX2 ? 8 : 4; }

std::unique_ptr<KdTreeAccel> make_kd_simd_accel(KdTree tree, const BuildConfig& cfg, double build_ms) {
    const std::uint32_t width = cfg.kd_blocks.width ? cfg.kd_blocks.width : default_kd_block_width();
#if XSIMD_WITH_AVX512F
    if (width == 16) return std::make_unique<KdSimdAccel<16>>(std::move(tree), cfg, build_ms);
#endif
    (void)width;
#if XSIMD_WITH_AVX2
    return std::make_unique<KdSimdAccel<8>>(std::move(tree), cfg, build_ms);
#else
    // SSE4.2 only (the portable build's sse4 kernel set): blocks of 4 triangles.
    return std::make_unique<KdSimdAccel<4>>(std::move(tree), cfg, build_ms);
#endif
}

}  // namespace arbor::accel::kset
