// The kd-tree's Accel: the rope walk alone, or with the SIMD paths of the kernel set in use, over
// its leaves' blocks (ropes) or over its cells as a wide BVH (make_accel.h).
#include "accel/dispatch/kernel_entries.h"
#include "accel/factory/make_accel.h"
#include "accel/kdtree/kdtree_build.h"
#include "accel/structures/kdtree_cells.h"
#include "accel/util/timer.h"

namespace arbor::accel {

std::unique_ptr<KdTreeAccel> make_kdtree_accel(KdTree tree, const BuildConfig& cfg, double build_ms) {
    if (cfg.layouts == Layouts::scalar) return std::unique_ptr<KdTreeAccel>(new KdTreeAccel(std::move(tree), cfg, build_ms));
    if (cfg.kd_blocks.walk != KdWalk::ropes) {
        KdCellPaths paths;
        paths.make = [](const BinaryBvh& cells, const TriangleView& prims, const BuildConfig& wide_cfg) {
            return make_wide_bvh_accel(AccelKind::kdtree, cells, prims, wide_cfg, 0.0);
        };
        paths.width = wide_width_or_default(cfg.wide.width);
        return make_kd_cell_accel(std::move(tree), cfg, build_ms, paths);
    }
    return make_kd_simd_accel(std::move(tree), cfg, build_ms);
}

std::unique_ptr<KdTreeAccel> make_kdtree_accel(const TriangleView& tris, const BuildConfig& cfg) {
    const Timer timer;
    KdTree tree = build_kdtree(tris, cfg.kd, cfg.max_memory);
    return make_kdtree_accel(std::move(tree), cfg, timer.ms());
}

}  // namespace arbor::accel
