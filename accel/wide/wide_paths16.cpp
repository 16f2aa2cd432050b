// The SIMD paths of 16-wide BVH layouts (one width per translation unit).
#include "accel/wide/wide_paths_impl.h"

namespace arbor::accel {
#if XSIMD_WITH_AVX512F
template <>
std::unique_ptr<WidePaths> make_wide_paths_n<16>(const BinaryBvh& bvh, const TriangleView& tris, const WideConfig& cfg) {
    return std::make_unique<WidePathsN<16>>(bvh, tris, cfg);
}
#endif
}  // namespace arbor::accel
