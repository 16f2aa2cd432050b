#include "accel/bvh_build.h"
#include "accel/bvh_top_down.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cfloat>
#include <limits>

namespace arbor::accel {

namespace {

using detail::BuildPrim;
using detail::BuildTask;
using detail::SplitResult;

constexpr std::uint32_t max_bins = 64;
/// From this depth on only median splits are made (each halves the range: at most 32 more levels).
constexpr std::uint32_t sah_depth_limit = 48;
/// Ranges of at least this many primitives are binned by several tasks (tbb::parallel_reduce).
constexpr std::uint32_t parallel_binning = 32 * 1024;

/// Maps a centroid to its bin on each axis. Works on halves (c/2 - lo/2) so that nothing overflows
/// near FLT_MAX; the scale is computed in double and clamped, so a tiny extent cannot make it inf.
struct BinMap {
    std::uint32_t bins = 16;
    float lo_half[3] = {}, scale[3] = {};
    bool usable[3] = {};

    BinMap(const Bounds& cbox, std::uint32_t bin_count) : bins(bin_count) {
        for (int a = 0; a < 3; ++a) {
            const double extent = double(cbox.hi[a]) - double(cbox.lo[a]);
            usable[a] = extent > 0.0;
            lo_half[a] = cbox.lo[a] * 0.5f;
            scale[a] = usable[a] ? float(std::min(2.0 * bins / extent, double(FLT_MAX))) : 0.0f;
        }
    }
    std::uint32_t bin(const BuildPrim& p, int a) const {
        const float f = (p.centroid(a) * 0.5f - lo_half[a]) * scale[a];
        return std::uint32_t(std::clamp(f, 0.0f, float(bins - 1)));
    }
};

struct Bins {
    Bounds box[3][max_bins];
    std::uint32_t count[3][max_bins] = {};

    void add(std::span<const BuildPrim> prims, std::uint32_t begin, std::uint32_t end, const BinMap& map) {
        for (std::uint32_t i = begin; i < end; ++i) {
            const BuildPrim& p = prims[i];
            const Bounds b = p.box();
            for (int a = 0; a < 3; ++a) {
                if (!map.usable[a]) continue;
                const std::uint32_t k = map.bin(p, a);
                box[a][k].grow(b);
                ++count[a][k];
            }
        }
    }
    /// Exact (min/max and integer sums), so the merge order of parallel tasks does not matter.
    void merge(const Bins& o, std::uint32_t bins) {
        for (int a = 0; a < 3; ++a)
            for (std::uint32_t k = 0; k < bins; ++k) box[a][k].grow(o.box[a][k]), count[a][k] += o.count[a][k];
    }
};

/// Hoare partition of [begin, end) by `left(p)`, collecting the bounds of both sides on the way.
template <class Pred>
SplitResult partition_range(std::span<BuildPrim> prims, const BuildTask& t, Pred left) {
    SplitResult s;
    std::uint32_t i = t.begin, j = t.end;
    auto take = [](const BuildPrim& p, Bounds& box, Bounds& cbox) {
        box.grow(p.box());
        cbox.grow(Vec3f{p.centroid(0), p.centroid(1), p.centroid(2)});
    };
    for (;;) {
        while (i < j && left(prims[i])) take(prims[i++], s.left_box, s.left_cbox);
        while (i < j && !left(prims[j - 1])) take(prims[--j], s.right_box, s.right_cbox);
        if (i >= j) break;
        std::swap(prims[i], prims[j - 1]);
        take(prims[i++], s.left_box, s.left_cbox);
        take(prims[--j], s.right_box, s.right_cbox);
    }
    s.mid = i;
    return s;
}

struct SahSplitter {
    const BuildConfig& cfg;
    std::uint32_t max_leaf, bins;

    std::optional<SplitResult> operator()(std::span<BuildPrim> prims, const BuildTask& t) const {
        const std::uint32_t n = t.size();
        if (n == 1) return std::nullopt;
        const int longest = detail::longest_axis(t.cbox);
        if (longest < 0) {  // all centroids equal: no split separates anything
            if (n <= max_leaf) return std::nullopt;
            return detail::index_median_split(prims, t);
        }
        if (t.depth >= sah_depth_limit) {
            if (n <= max_leaf) return std::nullopt;
            return detail::object_median_split(prims, t, longest);
        }
        const BinMap map(t.cbox, bins);
        Bins b;
        if (n >= parallel_binning) {
            b = tbb::parallel_reduce(
                tbb::blocked_range<std::uint32_t>(t.begin, t.end, 8192), Bins{},
                [&](const tbb::blocked_range<std::uint32_t>& r, Bins acc) {
                    acc.add(prims, r.begin(), r.end(), map);
                    return acc;
                },
                [&](Bins x, const Bins& y) {
                    x.merge(y, bins);
                    return x;
                });
        } else {
            b.add(prims, t.begin, t.end, map);
        }

        // Sweep the bin boundaries of every usable axis: cost = area(L) * |L| + area(R) * |R|.
        double best_cost = std::numeric_limits<double>::infinity();
        int best_axis = -1;
        std::uint32_t best_bin = 0;
        for (int a = 0; a < 3; ++a) {
            if (!map.usable[a]) continue;
            double right_area[max_bins];
            std::uint32_t right_count[max_bins];
            Bounds acc;
            std::uint32_t cnt = 0;
            for (std::uint32_t k = bins - 1; k > 0; --k) {
                acc.grow(b.box[a][k]);
                cnt += b.count[a][k];
                right_area[k] = acc.area();
                right_count[k] = cnt;
            }
            acc = {};
            cnt = 0;
            for (std::uint32_t k = 1; k < bins; ++k) {
                acc.grow(b.box[a][k - 1]);
                cnt += b.count[a][k - 1];
                if (cnt == 0 || right_count[k] == 0) continue;
                const double cost = acc.area() * cnt + right_area[k] * right_count[k];
                if (cost < best_cost) best_cost = cost, best_axis = a, best_bin = k;
            }
        }
        if (n <= max_leaf) {
            const double area = t.box.area();
            if (best_axis < 0 || !(area > 0.0)) return std::nullopt;
            const double split_cost = cfg.traversal_cost + cfg.intersection_cost * best_cost / area;
            if (double(cfg.intersection_cost) * n <= split_cost) return std::nullopt;
        }
        if (best_axis < 0) return detail::object_median_split(prims, t, longest);  // binning could not separate
        return partition_range(prims, t, [&](const BuildPrim& p) { return map.bin(p, best_axis) < best_bin; });
    }
};

}  // namespace

BinaryBvh build_bvh_sah(const PrimRefs& refs, const BuildConfig& cfg) {
    const SahSplitter split{cfg, std::max<std::uint32_t>(cfg.max_leaf_size, 1), std::clamp<std::uint32_t>(cfg.sah_bins, 2, max_bins)};
    return detail::build_top_down(refs, cfg, split);
}

}  // namespace arbor::accel
