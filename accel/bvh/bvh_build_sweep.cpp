#include "accel/bvh/bvh_build.h"
#include "accel/bvh/bvh_top_down.h"

#include <algorithm>
#include <limits>

namespace arbor::accel {

namespace {

using detail::BuildPrim;
using detail::BuildTask;
using detail::SplitResult;

constexpr std::uint32_t sweep_depth_limit = 48;

void sort_by_axis(std::span<BuildPrim> prims, const BuildTask& t, int a) {
    std::sort(prims.begin() + t.begin, prims.begin() + t.end, [a](const BuildPrim& x, const BuildPrim& y) {
        const float cx = x.centroid(a), cy = y.centroid(a);
        return cx < cy || (cx == cy && x.id < y.id);
    });
}

struct SweepSplitter {
    const BvhBuildConfig& cfg;
    std::uint32_t max_leaf;

    std::optional<SplitResult> operator()(std::span<BuildPrim> prims, const BuildTask& t) const {
        const std::uint32_t n = t.size();
        if (n <= std::max<std::uint32_t>(cfg.leaf_floor, 1)) return std::nullopt;
        const int longest = detail::longest_axis(t.cbox);
        if (longest < 0 || t.depth >= sweep_depth_limit) {
            if (n <= max_leaf) return std::nullopt;
            return longest < 0 ? detail::index_median_split(prims, t) : detail::object_median_split(prims, t, longest);
        }
        double best_cost = std::numeric_limits<double>::infinity();
        int best_axis = -1;
        std::uint32_t best_left = 0;
        std::vector<double> right_area(n);
        for (int a = 0; a < 3; ++a) {
            sort_by_axis(prims, t, a);
            Bounds acc;
            for (std::uint32_t k = n; k-- > 1;) {
                acc.grow(prims[t.begin + k].box());
                right_area[k] = acc.area();
            }
            acc = {};
            for (std::uint32_t k = 1; k < n; ++k) {  // k primitives on the left
                acc.grow(prims[t.begin + k - 1].box());
                const double cost = acc.area() * k + right_area[k] * (n - k);
                if (cost < best_cost) best_cost = cost, best_axis = a, best_left = k;
            }
        }
        if (n <= max_leaf) {
            const double area = t.box.area();
            if (!(area > 0.0)) return std::nullopt;
            const double split_cost = cfg.traversal_cost + cfg.intersection_cost * best_cost / area;
            if (double(cfg.intersection_cost) * n <= split_cost) return std::nullopt;
        }
        sort_by_axis(prims, t, best_axis);
        return detail::bounds_of_halves(prims, t.begin, t.begin + best_left, t.end);
    }
};

}  // namespace

BinaryBvh build_bvh_sah_sweep(const PrimRefs& refs, const BvhBuildConfig& cfg) {
    const SweepSplitter split{cfg, std::max<std::uint32_t>(cfg.max_leaf_size, 1)};
    return detail::build_top_down(make_build_prims(refs), cfg, split);
}

}  // namespace arbor::accel
