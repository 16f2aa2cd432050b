#include "accel/bvh/bvh_build.h"
#include "accel/bvh/bvh_top_down.h"

#include <algorithm>
#include <utility>

namespace arbor::accel {

namespace {

struct MedianSplitter {
    std::uint32_t max_leaf;

    std::optional<detail::SplitResult> operator()(std::span<detail::BuildPrim> prims, const detail::BuildTask& t) const {
        if (t.size() <= max_leaf) return std::nullopt;
        const int axis = detail::longest_axis(t.cbox);
        if (axis < 0) return detail::index_median_split(prims, t);  // all centroids equal
        return detail::object_median_split(prims, t, axis);
    }
};

}  // namespace

BinaryBvh build_bvh_median(BuildPrims&& prims, const BvhBuildConfig& cfg) {
    const MedianSplitter split{std::max<std::uint32_t>({cfg.max_leaf_size, cfg.leaf_floor, 1u})};
    return detail::build_top_down(std::move(prims), cfg, split);
}

BinaryBvh build_bvh_median(const PrimRefs& refs, const BvhBuildConfig& cfg) { return build_bvh_median(make_build_prims(refs), cfg); }

}  // namespace arbor::accel
