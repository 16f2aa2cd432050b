#include "accel/bvh/bvh_build.h"
#include "accel/bvh/bvh_top_down.h"
#include "accel/bvh/sah_bin_box.h"
#include "simd/simd.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/spin_mutex.h>

#include <algorithm>
#include <cfloat>
#include <limits>
#include <utility>

namespace arbor::accel {

namespace {

using detail::BinBox;
using detail::BinLanes;
using detail::BuildPrim;
using detail::BuildTask;
using detail::SplitResult;
using F4 = simd::Float4;  // x, y, z and an unused lane

constexpr std::uint32_t max_bins = 32;
/// Ranges of at most this many primitives are split by an exact sweep over their centroids sorted
/// on the longest axis of the centroid bounds: a third of the cost of binning them (measured with
/// callgrind on the bunny: 178M instead of 210M instructions for the whole build, SAH cost +0.6%).
constexpr std::uint32_t small_range = 16;
/// Ranges of at least this many primitives are binned by several tasks (tbb::parallel_for).
constexpr std::uint32_t parallel_binning = 32 * 1024;
/// A root of at least this many primitives is partitioned by two tasks (partition_halves).
constexpr std::uint32_t parallel_partition = 64 * 1024;

constexpr float inf = std::numeric_limits<float>::infinity();

inline F4 f4(float x, float y, float z, float w) {
    alignas(16) const float v[4] = {x, y, z, w};
    return F4::load_aligned(v);
}

/// A box with all three axes in one SSE register each (lane 3 unused).
struct Box4 {
    F4 lo = F4(inf), hi = F4(-inf);

    void grow(const F4& l, const F4& h) { lo = xsimd::min(lo, l), hi = xsimd::max(hi, h); }
    void grow(const Box4& b) { grow(b.lo, b.hi); }
    Bounds bounds() const {
        alignas(16) float l[4], h[4];
        lo.store_aligned(l), hi.store_aligned(h);
        return {{l[0], l[1], l[2]}, {h[0], h[1], h[2]}};
    }
    static Box4 of(const Bounds& b) { return {f4(b.lo.x, b.lo.y, b.lo.z, 0.0f), f4(b.hi.x, b.hi.y, b.hi.z, 0.0f)}; }
};

/// Lanes x, y, z of a 4-lane register.
const F4::batch_bool_type xyz_lanes = f4(0, 1, 2, 3) < F4(2.5f);

/// A build primitive in registers: box and centroid (lo/2 + hi/2, as BuildPrim::centroid).
struct Prim4 {
    F4 lo, hi, c;
    explicit Prim4(const BuildPrim& p) {
        lo = xsimd::select(xyz_lanes, F4::load_aligned(p.lo), F4(0.0f));  // lane 3 holds the id's bits
        hi = F4::load_aligned(p.hi);                                 // lane 3 holds pad = 0
        c = lo * F4(0.5f) + hi * F4(0.5f);
    }
};

/// Half the surface area of `b` after scaling it by `s`. Boxes inside the node scaled by the
/// inverse of the node's largest half extent have half extents <= 1, so nothing overflows even
/// near FLT_MAX; SAH costs only compare areas, so the common factor s^2 does not matter.
inline float scaled_half_area(const Box4& b, const F4& s) {
    const F4 d = (b.hi * F4(0.5f) - b.lo * F4(0.5f)) * s;
    alignas(16) float e[4];
    d.store_aligned(e);
    return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
}

inline F4 node_scale(const Bounds& box) {
    float m = 0.0f;
    for (int a = 0; a < 3; ++a) m = std::max(m, box.hi[a] * 0.5f - box.lo[a] * 0.5f);
    return F4(m > 0.0f ? std::min(1.0f / m, FLT_MAX) : 1.0f);
}

/// Maps centroids to bins, all three axes at once. Works on halves (c/2 - lo/2) so that nothing
/// overflows near FLT_MAX; the scale is computed in double and clamped, so a tiny extent cannot
/// make it inf. An axis without extent gets scale 0 (every centroid in bin 0) and is not swept.
struct BinMap {
    std::uint32_t bins = 16;
    F4 lo_half, scale, top;
    bool usable[3] = {};

    BinMap(const Bounds& cbox, std::uint32_t bin_count) : bins(bin_count), top(float(bin_count - 1)) {
        alignas(16) float s[4] = {0, 0, 0, 0};
        for (int a = 0; a < 3; ++a) {
            const double extent = double(cbox.hi[a]) - double(cbox.lo[a]);
            usable[a] = extent > 0.0;
            s[a] = usable[a] ? float(std::min(2.0 * bins / extent, double(FLT_MAX))) : 0.0f;
        }
        scale = F4::load_aligned(s);
        lo_half = f4(cbox.lo.x * 0.5f, cbox.lo.y * 0.5f, cbox.lo.z * 0.5f, 0.0f);
    }
    /// Bin of the centroid on each axis (k[3] is meaningless).
    void bin(const F4& c, std::int32_t* k) const {
        const F4 f = (c * F4(0.5f) - lo_half) * scale;
        xsimd::batch_cast<std::int32_t>(xsimd::min(xsimd::max(f, F4(0.0f)), top)).store_aligned(k);
    }
};

/// Per-axis bins: box and centroid box (BinBox, sah_bin_box.h) and primitive count. Only the first
/// `bins` entries are initialised and used (a small node would otherwise spend more on clearing 32
/// bins than on binning its primitives).
struct Bins {
    std::uint32_t bins;
    BinBox box[3][max_bins];
    std::uint32_t count[3][max_bins];

    explicit Bins(std::uint32_t bin_count) : bins(bin_count) {
        for (int a = 0; a < 3; ++a)
            for (std::uint32_t k = 0; k < bins; ++k) box[a][k].clear(), count[a][k] = 0;
    }
    void add(const Prim4& p, const BinMap& map) {
        alignas(16) std::int32_t k[4];
        map.bin(p.c, k);
        const BinLanes r = BinLanes::prim(p.lo, p.hi, p.c);
        for (int a = 0; a < 3; ++a) box[a][k[a]].grow(r), ++count[a][k[a]];
    }
    /// Bins [begin, end) of `prims`, two primitives per step into this and a second set of bins:
    /// consecutive primitives often fall into the same bin, and with one set each box update
    /// would wait for the previous one's store (a store-to-load chain of ~6 cycles per primitive).
    void add(std::span<const BuildPrim> prims, std::uint32_t begin, std::uint32_t end, const BinMap& map) {
        Bins other(bins);
        std::uint32_t i = begin;
        for (; i + 1 < end; i += 2) add(Prim4(prims[i]), map), other.add(Prim4(prims[i + 1]), map);
        if (i < end) add(Prim4(prims[i]), map);
        merge(other);
    }
    /// Exact (minima of values without -0, and integer sums): the merge order does not matter.
    void merge(const Bins& o) {
        for (int a = 0; a < 3; ++a)
            for (std::uint32_t k = 0; k < bins; ++k) box[a][k].grow(o.box[a][k]), count[a][k] += o.count[a][k];
    }
    /// Box and centroid box of bins [begin, end) on `axis`.
    BinBox range(int axis, std::uint32_t begin, std::uint32_t end) const {
        BinBox u;
        u.clear();
        for (std::uint32_t k = begin; k < end; ++k) u.grow(box[axis][k]);
        return u;
    }
};

/// The split found by a sweep: axis (-1: none), position, and cost area(L)|L| + area(R)|R| in
/// scaled half areas.
struct Candidate {
    int axis = -1;
    std::uint32_t pos = 0;
    float cost = inf;
};

/// A bin's box (without its centroid box) in registers.
inline Box4 box4(const BinBox& b) { return {F4::load_unaligned(b.v), F4(0.0f) - F4::load_unaligned(b.v + 4)}; }

Candidate sweep_bins(const Bins& b, const BinMap& map, const F4& s) {
    Candidate best;
    for (int a = 0; a < 3; ++a) {
        if (!map.usable[a]) continue;
        float right_area[max_bins];
        std::uint32_t right_count[max_bins];
        Box4 acc;
        std::uint32_t cnt = 0;
        for (std::uint32_t k = map.bins - 1; k > 0; --k) {
            acc.grow(box4(b.box[a][k]));
            cnt += b.count[a][k];
            right_area[k] = scaled_half_area(acc, s);
            right_count[k] = cnt;
        }
        acc = {};
        cnt = 0;
        for (std::uint32_t k = 1; k < map.bins; ++k) {
            acc.grow(box4(b.box[a][k - 1]));
            cnt += b.count[a][k - 1];
            if (cnt == 0 || right_count[k] == 0) continue;
            const float cost = scaled_half_area(acc, s) * float(cnt) + right_area[k] * float(right_count[k]);
            if (cost < best.cost) best = {a, k, cost};
        }
    }
    return best;
}

/// Bounds of [begin, mid) and [mid, end) after the range was put in order.
SplitResult halves(std::span<const BuildPrim> prims, std::uint32_t begin, std::uint32_t mid, std::uint32_t end) {
    Box4 box[2], cbox[2];
    for (std::uint32_t i = begin; i < end; ++i) {
        const Prim4 p(prims[i]);
        const int side = i < mid ? 0 : 1;
        box[side].grow(p.lo, p.hi), cbox[side].grow(p.c, p.c);
    }
    return {mid, box[0].bounds(), cbox[0].bounds(), box[1].bounds(), cbox[1].bounds()};
}

/// Which side of a split a primitive goes to: the binning arithmetic on the split's axis in scalar
/// code (the same operations as BinMap::bin's lane, so a primitive goes to the side it was counted
/// on: the bins give both sides' bounds, see split_of_bins).
struct SideTest {
    float lo_a, scale_a;
    __m128 top;
    int axis;
    std::uint32_t split_bin;

    SideTest(const BinMap& map, int a, std::uint32_t split) : top(_mm_set_ss(float(map.bins - 1))), axis(a), split_bin(split) {
        alignas(16) float lo_half[4], scale[4];
        map.lo_half.store_aligned(lo_half), map.scale.store_aligned(scale);
        lo_a = lo_half[axis], scale_a = scale[axis];
    }
    bool left(const BuildPrim& p) const {  // maxss/minss: the lane operations of xsimd::max/min, no branch
        const __m128 f = _mm_set_ss((p.centroid(axis) * 0.5f - lo_a) * scale_a);
        return std::uint32_t(_mm_cvttss_si32(_mm_min_ss(_mm_max_ss(f, _mm_setzero_ps()), top))) < split_bin;
    }
};

/// Partitions [begin, end) into the primitives left of the split, then those right of it; returns
/// the first index of the right side. Blocks of `block` primitives from both ends are first only
/// tested, without a branch per primitive, noting where the misplaced ones are; then those are
/// swapped in pairs (Edelkamp & Weiss, "BlockQuicksort: Avoiding Branch Mispredictions in
/// Quicksort", ESA 2016). A Hoare partition's branch per primitive is mispredicted about every
/// other time where the sides are mixed (profile of the 4.4M-triangle build: 21% of the process in
/// that partition). What is left in the middle, under two blocks, gets a branch-free Lomuto loop.
/// The order depends only on the input, not on the thread count.
std::uint32_t partition_range(std::span<BuildPrim> prims, std::uint32_t begin, std::uint32_t end, const SideTest& side) {
    constexpr std::uint32_t block = 128;
    std::uint8_t off_l[block], off_r[block];  // misplaced: right-side primitives in the left block, and vice versa
    std::uint32_t i = begin, j = end;  // [begin, i) left, [j, end) right
    std::uint32_t nl = 0, nr = 0, sl = 0, sr = 0;  // misplaced offsets not yet swapped: off_l[sl, sl + nl), ...
    BuildPrim* p = prims.data();
    while (j - i > 2 * block) {
        if (nl == 0) {
            sl = 0;
            for (std::uint32_t k = 0; k < block; ++k) off_l[nl] = std::uint8_t(k), nl += side.left(p[i + k]) ? 0 : 1;
        }
        if (nr == 0) {
            sr = 0;
            for (std::uint32_t k = 0; k < block; ++k) off_r[nr] = std::uint8_t(k), nr += side.left(p[j - 1 - k]) ? 1 : 0;
        }
        const std::uint32_t m = std::min(nl, nr);
        for (std::uint32_t k = 0; k < m; ++k) std::swap(p[i + off_l[sl + k]], p[j - 1 - off_r[sr + k]]);
        nl -= m, nr -= m, sl += m, sr += m;
        if (nl == 0) i += block;  // the left block holds left primitives only
        if (nr == 0) j -= block;
    }
    // The rest (a block with misplaced primitives left is part of it), and all of a small range:
    // Lomuto's partition without a branch, [i, w) left and [w, k) right: every primitive is
    // swapped to w, which moves on past the left ones.
    std::uint32_t w = i;
    for (std::uint32_t k = i; k < j; ++k) {
        const BuildPrim x = p[k];
        const std::uint32_t l = side.left(x) ? 1 : 0;
        p[k] = p[w];
        p[w] = x;
        w += l;
    }
    return w;
}

/// partition_range as two tasks, for the root (the one range no other task runs beside): each
/// half of [begin, end) is partitioned on its own, then the right run of the first half and the
/// left run of the second trade places (min of their lengths swapped). The halves are fixed, so
/// the order is the same for any thread count.
std::uint32_t partition_halves(std::span<BuildPrim> prims, std::uint32_t begin, std::uint32_t end, const SideTest& side) {
    const std::uint32_t half = begin + (end - begin) / 2;
    std::uint32_t m1 = 0, m2 = 0;
    tbb::parallel_invoke([&] { m1 = partition_range(prims, begin, half, side); }, [&] { m2 = partition_range(prims, half, end, side); });
    // [begin, m1) left, [m1, half) right, [half, m2) left, [m2, end) right.
    const std::uint32_t right1 = half - m1, left2 = m2 - half, k = std::min(right1, left2);
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, k, 65536), [&](const tbb::blocked_range<std::uint32_t>& r) {
        for (std::uint32_t i = r.begin(); i != r.end(); ++i) std::swap(prims[m1 + i], prims[m2 - k + i]);
    });
    return m1 + left2;
}

/// The split of [begin, end) at `mid` after partition_range, with both sides' bounds from the bins.
SplitResult split_of_bins(const Bins& b, int axis, std::uint32_t split_bin, std::uint32_t mid) {
    const BinBox l = b.range(axis, 0, split_bin), r = b.range(axis, split_bin, b.bins);
    return {mid, l.box(), l.centroid_box(), r.box(), r.centroid_box()};
}

struct SahSplitter {
    const BvhBuildConfig& cfg;
    std::uint32_t max_leaf, bins;

    /// SAH: a leaf costs intersection_cost * n, a split traversal_cost + intersection_cost *
    /// (area(L) |L| + area(R) |R|) / area(node). A node without area (or split) stays a leaf.
    bool leaf_is_cheaper(const BuildTask& t, const Candidate& c, const F4& s) const {
        const float area = scaled_half_area(Box4::of(t.box), s);
        if (c.axis < 0 || !(area > 0.0f)) return true;
        return cfg.intersection_cost * float(t.size()) <= cfg.traversal_cost + cfg.intersection_cost * c.cost / area;
    }

    std::optional<SplitResult> split_small(std::span<BuildPrim> prims, const BuildTask& t, int axis, const F4& s) const {
        const std::uint32_t n = t.size();
        BuildPrim* p = prims.data() + t.begin;
        Box4 box[small_range];
        float key[small_range];
        std::uint8_t order[small_range];
        for (std::uint32_t i = 0; i < n; ++i) {
            const Prim4 q(p[i]);
            box[i] = {q.lo, q.hi};
            key[i] = p[i].centroid(axis);
            std::uint32_t j = i;  // stable insertion sort: ties keep their position
            for (; j > 0 && key[order[j - 1]] > key[i]; --j) order[j] = order[j - 1];
            order[j] = std::uint8_t(i);
        }
        float right_area[small_range];
        Box4 acc;
        for (std::uint32_t k = n - 1; k > 0; --k) {
            acc.grow(box[order[k]]);
            right_area[k] = scaled_half_area(acc, s);
        }
        acc = {};
        Candidate best;
        for (std::uint32_t k = 1; k < n; ++k) {
            acc.grow(box[order[k - 1]]);
            const float cost = scaled_half_area(acc, s) * float(k) + right_area[k] * float(n - k);
            if (cost < best.cost) best = {axis, k, cost};
        }
        if (n <= max_leaf && leaf_is_cheaper(t, best, s)) return std::nullopt;
        BuildPrim sorted[small_range];
        for (std::uint32_t i = 0; i < n; ++i) sorted[i] = p[order[i]];
        std::copy(sorted, sorted + n, p);
        return halves(prims, t.begin, t.begin + best.pos, t.end);
    }

    std::optional<SplitResult> operator()(std::span<BuildPrim> prims, const BuildTask& t) const {
        const std::uint32_t n = t.size();
        if (n <= std::max<std::uint32_t>(cfg.leaf_floor, 1)) return std::nullopt;
        const int longest = detail::longest_axis(t.cbox);
        if (longest < 0) {  // all centroids equal: no split separates anything
            if (n <= max_leaf) return std::nullopt;
            return detail::index_median_split(prims, t);
        }
        if (t.depth >= cfg.sah_depth_limit) {
            if (n <= max_leaf) return std::nullopt;
            return detail::object_median_split(prims, t, longest);
        }
        const F4 s = node_scale(t.box);
        if (n <= small_range) return split_small(prims, t, longest, s);
        // Fewer bins for small ranges (Embree's rule, 4 + n/20): clearing and sweeping 16 bins
        // per axis costs more than binning 30 primitives, and the exact sweep below small_range
        // picks up what coarse bins miss (bunny: SAH cost +0.4%).
        const std::uint32_t nb = std::min<std::uint32_t>(bins, 4 + n / 20);
        const BinMap map(t.cbox, nb);
        Bins b(nb);
        if (n >= parallel_binning) {
            // Each task bins its ranges into bins of its own, merged into `b` under a lock (exact:
            // the same bins whatever the ranges and the order).
            tbb::spin_mutex lock;
            tbb::parallel_for(tbb::blocked_range<std::uint32_t>(t.begin, t.end, 8192), [&](const tbb::blocked_range<std::uint32_t>& r) {
                Bins part(nb);
                part.add(prims, r.begin(), r.end(), map);
                const tbb::spin_mutex::scoped_lock hold(lock);
                b.merge(part);
            });
        } else {
            b.add(prims, t.begin, t.end, map);
        }
        const Candidate best = sweep_bins(b, map, s);
        if (n <= max_leaf && leaf_is_cheaper(t, best, s)) return std::nullopt;
        if (best.axis < 0) return detail::object_median_split(prims, t, longest);  // binning could not separate
        const SideTest side(map, best.axis, best.pos);
        const std::uint32_t mid = t.depth == 0 && n >= parallel_partition ? partition_halves(prims, t.begin, t.end, side)
                                                                          : partition_range(prims, t.begin, t.end, side);
        return split_of_bins(b, best.axis, best.pos, mid);
    }
};

}  // namespace

BinaryBvh build_bvh_sah(BuildPrims&& prims, const BvhBuildConfig& cfg) {
    const SahSplitter split{cfg, std::max<std::uint32_t>(cfg.max_leaf_size, 1), std::clamp<std::uint32_t>(cfg.sah_bins, 2, max_bins)};
    return detail::build_top_down(std::move(prims), cfg, split);
}

BinaryBvh build_bvh_sah(const PrimRefs& refs, const BvhBuildConfig& cfg) { return build_bvh_sah(make_build_prims(refs), cfg); }

}  // namespace arbor::accel
