// The BVHs' Accel: the scalar layout, or the SIMD layout of the kernel set in use (make_accel.h).
#include "accel/dispatch/kernel_entries.h"
#include "accel/factory/make_accel.h"
#include "accel/core/memory_limit.h"
#include "accel/util/timer.h"

namespace arbor::accel {

std::unique_ptr<Accel> make_bvh_accel(AccelKind kind, BinaryBvh&& bvh, const TriangleView& tris,
                                      const BuildConfig& cfg, double build_ms) {
    if (cfg.layouts == Layouts::scalar && !cfg.compact)
        return std::make_unique<BvhAccel>(kind, bvh, tris, cfg, build_ms);
    // Under a memory limit, a SIMD-only build whose default layout would not fit is made in compact
    // mode when that fits: the layouts are checked from their sizes before they are allocated, so
    // the refused attempt cost its plan only. (With the scalar layout asked for, no: compact mode
    // has none.)
    if (cfg.max_memory == 0 || cfg.compact || cfg.layouts != Layouts::simd)
        return make_wide_bvh_accel(kind, bvh, tris, cfg, build_ms);
    check_binary_peak(kind, bvh, cfg.max_memory);  // (compact mode builds the same tree)
    std::string refused;
    try {
        return make_wide_bvh_accel(kind, bvh, tris, cfg, build_ms);
    } catch (const MemoryLimitError& e) {
        refused = e.what();
    }
    BuildConfig compact = cfg;
    compact.compact = true;
    std::unique_ptr<Accel> a;
    try {
        a = make_wide_bvh_accel(kind, bvh, tris, compact, build_ms);
    } catch (const MemoryLimitError& e) {
        // One line naming the structure and the limit once: "bvh-sah: its 16-wide SIMD layout needs
        // ... of max_memory = ...; in compact mode, its 16-wide compact layout needs ... left".
        std::string what = e.what();
        const std::string prefix = std::string(to_string(kind)) + ": ", suffix = " of " + max_memory_text(cfg.max_memory);
        if (what.starts_with(prefix)) what.erase(0, prefix.size());
        if (what.ends_with(suffix)) what.erase(what.size() - suffix.size());
        throw MemoryLimitError(refused + "; in compact mode, " + what);
    }
    a->note_compact_fallback(refused);
    return a;
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
    build_cfg.max_bytes = cfg.max_memory;         // (the top-down builders count their nodes against it)
    BinaryBvh bvh;
    try {
        bvh = builder(make_build_prims(tris), build_cfg);  // the build prims are gone after this line
    } catch (const MemoryLimitError& e) {
        throw MemoryLimitError(std::string(to_string(kind)) + ": " + e.what());
    }
    return make_bvh_accel(kind, std::move(bvh), tris, cfg, timer.ms());
}

}  // namespace arbor::accel
