// The SIMD paths of 4-wide BVH layouts (one width per translation unit).
#include "accel/structures/wide_paths_impl.h"

namespace arbor::accel {

template <>
std::unique_ptr<Accel> make_wide_bvh_accel_n<4>(AccelKind kind, const BinaryBvh& bvh, const TriangleView& tris,
                                                 const BuildConfig& cfg, double build_ms) {
    return std::make_unique<WideBvhAccel<4>>(kind, bvh, tris, cfg, build_ms);
}

}  // namespace arbor::accel
