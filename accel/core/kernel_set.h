#pragma once
/// The SIMD kernel set the traversal code of this build runs on, by name.
#include <string_view>

namespace arbor::accel {

/// "avx512" (AVX-512 F/BW/DQ/VL: 16-wide nodes and packets), "avx2" (AVX2 + FMA: 8-wide) or "sse4"
/// (SSE4.2: 4-wide).
std::string_view kernel_set();

}  // namespace arbor::accel
