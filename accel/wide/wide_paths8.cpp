// The SIMD paths of 8-wide BVH layouts (one width per translation unit).
#include "accel/wide/wide_paths_impl.h"

namespace arbor::accel {
#if XSIMD_WITH_AVX2
template <>
std::unique_ptr<WidePaths> make_wide_paths_n<8>(const BinaryBvh& bvh, const TriangleView& tris, const WideConfig& cfg) {
    return std::make_unique<WidePathsN<8>>(bvh, tris, cfg);
}
#endif
}  // namespace arbor::accel
