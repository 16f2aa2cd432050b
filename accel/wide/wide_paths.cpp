#include "accel/wide/wide_paths_impl.h"

namespace arbor::accel {

std::uint32_t default_wide_width() {
#if XSIMD_WITH_AVX512F
    return 16;
#else
    return 8;
#endif
}

std::uint32_t default_packet_lanes() { return wide_width_available<16>() ? 16 : 8; }

bool wide_width_supported(std::uint32_t width) {
    switch (width) {
    case 4: return true;
    case 8: return wide_width_available<8>();
    case 16: return wide_width_available<16>();
    default: return false;
    }
}

std::uint32_t wide_width_or_default(std::uint32_t width) {
    return wide_width_supported(width) ? width : default_wide_width();
}

std::unique_ptr<WidePaths> make_wide_paths(std::uint32_t width, const BinaryBvh& bvh, const TriangleView& tris,
                                           const WideConfig& cfg) {
    switch (wide_width_or_default(width)) {
    case 4: return make_wide_paths_n<4>(bvh, tris, cfg);
#if XSIMD_WITH_AVX2
    case 8: return make_wide_paths_n<8>(bvh, tris, cfg);
#endif
#if XSIMD_WITH_AVX512F
    case 16: return make_wide_paths_n<16>(bvh, tris, cfg);
#endif
    default: break;
    }
    return make_wide_paths_n<4>(bvh, tris, cfg);
}

}  // namespace arbor::accel
