// The wide BVHs' entries of a kernel set (kernel_table.h): the widths it has and the factory.
#include "accel/structures/wide_paths_impl.h"

namespace arbor::accel::kset {

std::uint32_t default_wide_width() {
#if XSIMD_WITH_AVX512F
    return 16;
#elif XSIMD_WITH_AVX2
    return 8;
#else
    return 4;
#endif
}

bool wide_width_supported(std::uint32_t width) {
    switch (width) {
    case 4: return true;
    case 8: return wide_width_available<8>();
    case 16: return wide_width_available<16>();
    default: return false;
    }
}

std::unique_ptr<Accel> make_wide_bvh_accel(AccelKind kind, const BinaryBvh& bvh, const TriangleView& tris,
                                           const BuildConfig& cfg, double build_ms) {
    if (cfg.compact)
        return make_compact_bvh_accel(wide_width_supported(cfg.wide.width) ? cfg.wide.width : default_wide_width(),
                                      kind, bvh, tris, cfg, build_ms);
    switch (wide_width_supported(cfg.wide.width) ? cfg.wide.width : default_wide_width()) {
#if XSIMD_WITH_AVX2
    case 8: return make_wide_bvh_accel_n<8>(kind, bvh, tris, cfg, build_ms);
#endif
#if XSIMD_WITH_AVX512F
    case 16: return make_wide_bvh_accel_n<16>(kind, bvh, tris, cfg, build_ms);
#endif
    default: break;
    }
    return make_wide_bvh_accel_n<4>(kind, bvh, tris, cfg, build_ms);
}

}  // namespace arbor::accel::kset
