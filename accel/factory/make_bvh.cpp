// The BVHs' Accel: the scalar layout, or the SIMD layout of the kernel set in use (make_accel.h).
#include "accel/dispatch/kernel_entries.h"
#include "accel/factory/make_accel.h"
#include "accel/util/timer.h"

namespace arbor::accel {

std::unique_ptr<Accel> make_bvh_accel(AccelKind kind, BinaryBvh&& bvh, const TriangleView& tris,
                                      const BuildConfig& cfg, double build_ms) {
    if (cfg.layouts == Layouts::scalar && !cfg.compact)
        return std::make_unique<BvhAccel>(kind, bvh, tris, cfg, build_ms);
    return make_wide_bvh_accel(kind, bvh, tris, cfg, build_ms);
}

std::uint32_t bvh_leaf_floor(const BuildConfig& cfg) {
    if (cfg.layouts != Layouts::simd && !cfg.compact) return 0;
    if (cfg.bvh.simd_leaf_floor != 0) return cfg.bvh.simd_leaf_floor;
    return wide_width_or_default(cfg.wide.width);
}

std::unique_ptr<Accel> build_bvh_accel(AccelKind kind, const TriangleView& tris, const BuildConfig& cfg,
                                       BvhPrimBuilder builder) {
    const Timer timer;
    BvhBuildConfig build_cfg = cfg.bvh;
    build_cfg.leaf_floor = bvh_leaf_floor(cfg);  // the N-wide leaves' blocks: no finer split
    BinaryBvh bvh = builder(make_build_prims(tris), build_cfg);  // the build prims are gone after this line
    return make_bvh_accel(kind, std::move(bvh), tris, cfg, timer.ms());
}

}  // namespace arbor::accel
