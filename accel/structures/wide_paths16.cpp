// The SIMD paths of 16-wide BVH layouts (one width per translation unit).
#include "accel/structures/wide_paths_impl.h"

namespace arbor::accel {
#if XSIMD_WITH_AVX512F
template <>
std::unique_ptr<Accel> make_wide_bvh_accel_n<16>(AccelKind kind, const BinaryBvh& bvh, const TriangleView& tris,
                                                 const BuildConfig& cfg, double build_ms) {
    return std::make_unique<WideBvhAccel<16>>(kind, bvh, tris, cfg, build_ms);
}
#endif
}  // namespace arbor::accel
