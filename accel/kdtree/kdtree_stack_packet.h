#pragma once
/// The stack walk of kdtree_stack.h for a packet of K rays whose directions share their sign bits
/// (Wald 2004, "Realtime Ray Tracing and Interactive Global Illumination", ch. 7: one walk of the
/// nodes for the whole packet, each ray masked in or out of a subtree). The lanes' split-plane
/// tests are one SIMD compare of their float boxes per node; only where lanes walk both sides are
/// the crossings and intervals computed, in double, lane by lane.
///
/// Every lane takes, at every node, the decisions of its own scalar walk (walk_stack): the same
/// double intervals, the same float boxes, the same near side (the shared signs), the same pushes
/// and, for closest hit, the same drops of pushed subtrees beyond its best hit. A lane that walks
/// only the far side of a node while others walk both waits, masked out, until the packet comes
/// back to that side, with its interval untouched (its scalar walk moves on directly, with the same
/// interval). So each lane is active in exactly the leaves of its scalar walk, in the same order,
/// and the answers (closest and any hit) are the scalar walk's.
#include "accel/kdtree/kdtree_stack.h"
#include "simd/simd.h"

#include <algorithm>
#include <bit>
#include <type_traits>
#include <cstdint>

namespace arbor::accel::kd {

namespace packet_detail {
/// The double batch of float lane type P's instruction set, and its masks as bits and from bits.
template <class P> using DoubleOf = xsimd::batch<double, typename P::arch_type>;
template <class D> ARBOR_INLINE typename D::batch_bool_type dmask(std::uint32_t bits) {
#if XSIMD_WITH_AVX512F
    if constexpr (std::is_base_of_v<xsimd::avx512f, typename D::arch_type>)
        return typename D::batch_bool_type(static_cast<__mmask8>(bits));
    else
#endif
    {
        using I = xsimd::batch<std::int64_t, typename D::arch_type>;
        alignas(64) std::int64_t pow2[D::size];
        for (std::size_t j = 0; j < D::size; ++j) pow2[j] = std::int64_t(1) << j;
        return xsimd::bool_cast((I(std::int64_t(bits)) & I::load_aligned(pow2)) != I(0));
    }
}
template <class D> ARBOR_INLINE std::uint32_t dbits(const typename D::batch_bool_type& m) {
#if XSIMD_WITH_AVX512F
    if constexpr (std::is_base_of_v<xsimd::avx512f, typename D::arch_type>) return std::uint32_t(static_cast<__mmask8>(m));
    else
#endif
#if XSIMD_WITH_AVX
    if constexpr (std::is_base_of_v<xsimd::avx, typename D::arch_type>)
        return std::uint32_t(_mm256_movemask_pd(static_cast<__m256d>(m)));
    else
#endif
        return std::uint32_t(_mm_movemask_pd(static_cast<__m128d>(m)));
}
}  // namespace packet_detail

template <std::size_t K> struct PacketStack {
    static_assert(K <= 32);
    /// A pushed subtree: the lanes that pushed it (their interval from the plane on, to be dropped
    /// beyond their best hit like the scalar walk's pushes) and the lanes that only walk this side
    /// (their interval as it was: their scalar walk went on without a push).
    struct Entry {
        alignas(64) double tmin[K];
        alignas(64) double tmax[K];
        std::uint32_t node, pushed, moved;
    };
    alignas(64) double o[3][K];
    alignas(64) double d[3][K];
    alignas(64) double rcp[3][K];
    alignas(64) double e[3][K];
    alignas(64) double tmin[K];
    alignas(64) double tmax[K];
    alignas(64) float lo[3][K];  ///< the lanes' boxes of their current intervals (StackWalk::lo, hi)
    alignas(64) float hi[3][K];
    std::uint32_t flat_bits[3] = {};      ///< lanes with d == +-0 on that axis: the box stays the origin
    bool neg[3];                          ///< the shared sign bits of the directions
    int sp = 0;
    Entry stack[kd_max_depth + 1];

    /// Lane i takes the scalar walk's state after stack_start (w.neg must be this packet's signs).
    void set_lane(std::size_t i, const StackWalk& w) {
        for (int k = 0; k < 3; ++k) {
            o[k][i] = w.o[k], d[k][i] = w.d[k], rcp[k][i] = w.rcp[k], e[k][i] = w.e[k];
            lo[k][i] = w.lo[k], hi[k][i] = w.hi[k];
            flat_bits[k] = (flat_bits[k] & ~(1u << i)) | (w.flat[k] ? 1u << i : 0u);
        }
        tmin[i] = w.tmin, tmax[i] = w.tmax;
    }
    /// Unused lanes: any finite state (they are masked out everywhere).
    void clear_lane(std::size_t i) {
        for (int k = 0; k < 3; ++k) {
            o[k][i] = d[k][i] = e[k][i] = 0.0, rcp[k][i] = 1.0;
            lo[k][i] = hi[k][i] = 0.0f;
            flat_bits[k] |= 1u << i;
        }
        tmin[i] = tmax[i] = 0.0;
    }

    /// stack_start for the lanes `group` at once (they must share the signs neg[]; set neg first),
    /// in double SIMD: every lane that stack_start would start gets exactly its state (the same
    /// IEEE operations in the same order; std::min / std::max spelled as the selects they are, so
    /// that ties of -0 and +0 pick the same operand), every other lane clear_lane's. `org`, `dir`,
    /// `tnear`, `tfar`: the packet's rays in SoA floats (K each). Returns the lanes started
    /// (stack_start true). One pass for the packet instead of K scalar starts: the scalar starts
    /// and the octant grouping before them were ~50% of the packet path on alligator primary rays
    /// (perf record, 1 thread).
    template <class P>
    ARBOR_INLINE std::uint32_t start(const KdTree& tree, const float (&org)[3][K], const float (&dir)[3][K],
                                     const float* tnear, const float* tfar, std::uint32_t group) {
        using D = packet_detail::DoubleOf<P>;
        using DM = typename D::batch_bool_type;
        constexpr std::size_t H = D::size;
        static_assert(2 * H == K);
        alignas(64) double tn[K], tf[K], a[3][K], b[3][K];
        alignas(64) float wdir[3][K];
        // The walk's direction (walk_direction, kdtree_walk_dir.h) per lane: a component whose
        // shear underflows is +-0.
        for (std::size_t i = 0; i < K; i += P::size) {
            const P x = P::load_aligned(dir[0] + i), y = P::load_aligned(dir[1] + i), z = P::load_aligned(dir[2] + i);
            const P dmax = xsimd::max(xsimd::abs(x), xsimd::max(xsimd::abs(y), xsimd::abs(z)));
            const P c[3] = {x, y, z};
            for (int k = 0; k < 3; ++k) {
                const auto under = shears_to_zero(c[k], dmax);
                xsimd::select(under, xsimd::copysign(P(0.0f), c[k]), c[k]).store_aligned(wdir[k] + i);
            }
        }
        for (int k = 0; k < 3; ++k)
            for (std::size_t i = 0; i < K; ++i) o[k][i] = org[k][i], d[k][i] = wdir[k][i];
        for (std::size_t i = 0; i < K; ++i) tn[i] = tnear[i], tf[i] = tfar[i];
        std::uint32_t live = 0, flat[3] = {};
        const D zero(0.0), one(1.0);
        for (std::size_t h = 0; h < K; h += H) {
            D ok[3], dk[3], rk[3], enter[3], leave[3];
            DM fl[3];
            DM outside(false);
            D t0 = D::load_aligned(tn + h), t1 = D::load_aligned(tf + h);
            for (int k = 0; k < 3; ++k) {
                ok[k] = D::load_aligned(o[k] + h), dk[k] = D::load_aligned(d[k] + h);
                fl[k] = dk[k] == zero;
                rk[k] = one / dk[k];
                const D blo(double(tree.box.lo[k])), bhi(double(tree.box.hi[k]));
                // flat_axis_can_hit per lane
                outside = outside || (fl[k] && (ok[k] < blo || ok[k] > bhi || DM(tree.box.lo[k] == tree.box.hi[k])));
                const D ta = (blo - ok[k]) * rk[k], tb = (bhi - ok[k]) * rk[k];
                enter[k] = xsimd::select(tb < ta, tb, ta);  // std::min(a, b)
                leave[k] = xsimd::select(ta < tb, tb, ta);  // std::max(a, b)
                t0 = xsimd::select(!fl[k] && t0 < enter[k], enter[k], t0);
                t1 = xsimd::select(!fl[k] && leave[k] < t1, leave[k], t1);
            }
            // stack_start: dmax = std::max({|d0|, |d1|, |d2|}) (finite, so the order does not
            // matter), scale = std::max(|t0|, |t1|).
            const D a0 = xsimd::abs(dk[0]), a1 = xsimd::abs(dk[1]), a2 = xsimd::abs(dk[2]);
            const D a12 = xsimd::select(a1 < a2, a2, a1), dmax = xsimd::select(a0 < a12, a12, a0);
            const D at0 = xsimd::abs(t0), at1 = xsimd::abs(t1);
            const D scale = xsimd::select(at0 < at1, at1, at0);
            t0 = D::load_aligned(tn + h), t1 = D::load_aligned(tf + h);
            D ek[3];
            for (int k = 0; k < 3; ++k) {
                ek[k] = xsimd::select(fl[k], zero, D(point_tolerance) * dmax * xsimd::abs(rk[k]) * scale);
                const D from = enter[k] - ek[k], to = leave[k] + ek[k];
                t0 = xsimd::select(!fl[k] && t0 < from, from, t0);
                t1 = xsimd::select(!fl[k] && to < t1, to, t1);
            }
            const DM ok_lanes = packet_detail::dmask<D>(group >> h) && !outside && t0 <= t1;
            live |= packet_detail::dbits<D>(ok_lanes) << h;
            for (int k = 0; k < 3; ++k) {
                const DM keep = ok_lanes && !fl[k];  // clear_lane's lanes count as flat
                flat[k] |= packet_detail::dbits<D>(!keep) << h;
                xsimd::select(ok_lanes, ok[k], zero).store_aligned(o[k] + h);
                xsimd::select(ok_lanes, dk[k], zero).store_aligned(d[k] + h);
                xsimd::select(ok_lanes, rk[k], one).store_aligned(rcp[k] + h);
                xsimd::select(ok_lanes, ek[k], zero).store_aligned(e[k] + h);
                (ok[k] + (t0 - ek[k]) * dk[k]).store_aligned(a[k] + h);  // stack_interval
                (ok[k] + (t1 + ek[k]) * dk[k]).store_aligned(b[k] + h);
            }
            xsimd::select(ok_lanes, t0, zero).store_aligned(tmin + h);
            xsimd::select(ok_lanes, t1, zero).store_aligned(tmax + h);
        }
        for (int k = 0; k < 3; ++k) {
            flat_bits[k] = flat[k];
            alignas(64) float fa[K], fb[K];
            for (std::size_t i = 0; i < K; ++i) fa[i] = float(a[k][i]), fb[i] = float(b[k][i]);
            const auto keep = simd::from_bits<P>(flat[k]);
            // Flat axes: the origin (clear_lane's lanes: 0).
            const P at = xsimd::select(simd::from_bits<P>(live), P::load_aligned(org[k]), P(0.0f));
            const P near_side = xsimd::select(keep, at, P::load_aligned(fa));
            const P far_side = xsimd::select(keep, at, P::load_aligned(fb));
            (neg[k] ? far_side : near_side).store_aligned(lo[k]);
            (neg[k] ? near_side : far_side).store_aligned(hi[k]);
        }
        return live;
    }

    /// stack_interval's box for every lane from its [tmin, tmax] (flat axes keep the origin);
    /// Far only: after only tmax changed, just the box's far side (hi, or lo on a negative axis).
    template <class P, bool FarOnly> ARBOR_INLINE void boxes() {
        using D = packet_detail::DoubleOf<P>;
        constexpr std::size_t H = D::size;
        static_assert(2 * H == K);
        alignas(64) double a[K], b[K];
        alignas(64) float fa[K], fb[K];
        for (int k = 0; k < 3; ++k) {
            for (std::size_t h = 0; h < K; h += H) {
                const D ok = D::load_aligned(o[k] + h), dk = D::load_aligned(d[k] + h), ek = D::load_aligned(e[k] + h);
                if constexpr (!FarOnly) (ok + (D::load_aligned(tmin + h) - ek) * dk).store_aligned(a + h);
                (ok + (D::load_aligned(tmax + h) + ek) * dk).store_aligned(b + h);
            }
            for (std::size_t i = 0; i < K; ++i) fb[i] = float(b[i]);
            if constexpr (!FarOnly)
                for (std::size_t i = 0; i < K; ++i) fa[i] = float(a[i]);
            const auto keep = simd::from_bits<P>(flat_bits[k]);
            float* far_side = neg[k] ? lo[k] : hi[k];
            xsimd::select(keep, P::load_aligned(far_side), P::load_aligned(fb)).store_aligned(far_side);
            if constexpr (!FarOnly) {
                float* near_side = neg[k] ? hi[k] : lo[k];
                xsimd::select(keep, P::load_aligned(near_side), P::load_aligned(fa)).store_aligned(near_side);
            }
        }
    }
};

/// Walks the leaves of the lanes `live` of `w` (each set up by set_lane from stack_start, all
/// with the signs w.neg) front to back: leaf_fn(leaf index, lanes) -> the lanes done (any hit:
/// those that found a hit; closest: 0). best_t[i]: lane i's best hit so far (+inf while none),
/// updated by leaf_fn (closest hit: pushed subtrees starting beyond it are dropped and
/// intervals end at it, as in stack_pop).
template <bool AnyHit, class P, std::size_t K, class LeafFn>
void walk_stack_packet(const KdTree& tree, PacketStack<K>& w, std::uint32_t live, const float* best_t, LeafFn&& leaf_fn) {
    static_assert(simd::lanes<P> == K);
    const KdNode* nodes = tree.nodes.data();
    std::uint32_t node = 0, m = live, done = 0;
    w.sp = 0;
    for (;;) {
        KdNode n = nodes[node];
        while (!n.is_leaf()) {
            const int k = n.axis();
            const P split(n.split);
            const std::uint32_t to_lo = simd::to_bits(P::load_aligned(w.lo[k]) <= split) & m;
            const std::uint32_t to_hi = simd::to_bits(P::load_aligned(w.hi[k]) >= split) & m;
            // As stack_descend: both sides, or the low one when the box reaches it, else the high one.
            const std::uint32_t both = to_lo & to_hi, need_lo = to_lo, need_hi = m & ~(to_lo & ~to_hi);
            const bool neg = w.neg[k];
            const std::uint32_t lo_child = node + 1, hi_child = n.index();
            const std::uint32_t near_lanes = neg ? need_hi : need_lo, far_lanes = neg ? need_lo : need_hi;
            const std::uint32_t near_child = neg ? hi_child : lo_child, far_child = neg ? lo_child : hi_child;
            if (far_lanes == 0 || near_lanes == 0) {
                node = far_lanes == 0 ? near_child : far_child;
                m = far_lanes == 0 ? near_lanes : far_lanes;
                n = nodes[node];
                continue;
            }
            // Lanes in `both` push the far side from the plane (- e) on and walk the near side up
            // to the plane (+ e); the far side's other lanes wait there with their interval.
            typename PacketStack<K>::Entry& s = w.stack[w.sp++];
            s.node = far_child, s.pushed = both, s.moved = far_lanes & ~both;
            {
                using D = packet_detail::DoubleOf<P>;
                constexpr std::size_t H = D::size;
                const D p(double(n.split));
                for (std::size_t h = 0; h < K; h += H) {
                    const auto b = packet_detail::dmask<D>(both >> h);
                    const D ts = (p - D::load_aligned(w.o[k] + h)) * D::load_aligned(w.rcp[k] + h);
                    const D ek = D::load_aligned(w.e[k] + h), from = ts - ek, to = ts + ek;
                    const D t0 = D::load_aligned(w.tmin + h), t1 = D::load_aligned(w.tmax + h);
                    xsimd::select(b && t0 < from, from, t0).store_aligned(s.tmin + h);  // std::max(tmin, from)
                    t1.store_aligned(s.tmax + h);
                    xsimd::select(b && to < t1, to, t1).store_aligned(w.tmax + h);      // std::min(tmax, to)
                }
            }
            w.template boxes<P, true>();
            node = near_child, m = near_lanes;
            n = nodes[node];
        }
        if constexpr (AnyHit) {
            done |= leaf_fn(n.index(), m);
            if (done == live) return;  // every lane has its hit: the pops would all come back empty
        } else {
            leaf_fn(n.index(), m);
        }
        // Next pushed subtree that some lane still walks (stack_pop).
        for (;;) {
            if (w.sp == 0) return;
            const typename PacketStack<K>::Entry& s = w.stack[--w.sp];
            using D = packet_detail::DoubleOf<P>;
            constexpr std::size_t H = D::size;
            std::uint32_t pushed = s.pushed & ~done;
            const std::uint32_t moved = s.moved & ~done;
            if constexpr (AnyHit) {
                if (pushed != 0) {
                    std::copy(s.tmin, s.tmin + K, w.tmin);
                    std::copy(s.tmax, s.tmax + K, w.tmax);
                }
            } else {
                alignas(64) double best[K];
                for (std::size_t i = 0; i < K; ++i) best[i] = best_t[i];
                std::uint32_t dropped = 0;
                for (std::size_t h = 0; h < K; h += H) {
                    const auto pm = packet_detail::dmask<D>(pushed >> h);
                    const D t0 = D::load_aligned(s.tmin + h), t1 = D::load_aligned(s.tmax + h), bt = D::load_aligned(best + h);
                    dropped |= packet_detail::dbits<D>(t0 > bt) << h;
                    t0.store_aligned(w.tmin + h);
                    xsimd::select(pm && bt < t1, bt, t1).store_aligned(w.tmax + h);  // std::min(s.tmax, best)
                }
                pushed &= ~dropped;
            }
            m = pushed | moved;
            if (m == 0) continue;
            // Only lanes that waited (moved): their intervals and boxes are as they left them.
            if (pushed != 0) w.template boxes<P, false>();
            node = s.node;
            break;
        }
    }
}

}  // namespace arbor::accel::kd
