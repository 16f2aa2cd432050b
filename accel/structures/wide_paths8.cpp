// The SIMD paths of 8-wide BVH layouts (one width per translation unit).
#include "accel/structures/wide_paths_impl.h"

namespace arbor::accel {
#if XSIMD_WITH_AVX2
template <>
std::unique_ptr<Accel> make_wide_bvh_accel_n<8>(AccelKind kind, const BinaryBvh& bvh, const TriangleView& tris,
                                                 const BuildConfig& cfg, double build_ms) {
    return std::make_unique<WideBvhAccel<8>>(kind, bvh, tris, cfg, build_ms);
}
#endif
}  // namespace arbor::accel
