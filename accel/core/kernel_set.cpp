#include "accel/core/kernel_set.h"

#include "simd/simd.h"

namespace arbor::accel {

std::string_view kernel_set() {
#if XSIMD_WITH_AVX512F
    return "avx512";
#elif XSIMD_WITH_AVX2
    return "avx2";
#else
    return "sse4";
#endif
}

}  // namespace arbor::accel
