// The SIMD paths of 4-wide BVH layouts (one width per translation unit).
#include "accel/wide/wide_paths_impl.h"

namespace arbor::accel {

template <>
std::unique_ptr<WidePaths> make_wide_paths_n<4>(const BinaryBvh& bvh, const TriangleView& tris, const WideConfig& cfg) {
    return std::make_unique<WidePathsN<4>>(bvh, tris, cfg);
}

}  // namespace arbor::accel
