// The table of this kernel set (compiled once per set; ARBOR_KERNEL_ENTRY names its entry:
// arbor_kernels_sse4, _avx2, _avx512 in a portable build, arbor_kernels_native otherwise).
#include "accel/dispatch/kernel_table.h"

#include "simd/simd.h"

#ifndef ARBOR_KERNEL_ENTRY
#define ARBOR_KERNEL_ENTRY arbor_kernels_native
#endif

namespace {

constexpr const char* set_name() {
#if XSIMD_WITH_AVX512F
    return "avx512";
#elif XSIMD_WITH_AVX2
    return "avx2";
#else
    return "sse4";
#endif
}

namespace k = arbor::accel::kset;
constexpr arbor::accel::KernelTable table{set_name(),           k::default_wide_width,     k::wide_width_supported,
                                          k::make_wide_bvh_accel, k::default_kd_block_width, k::make_kd_simd_accel};

}  // namespace

extern "C" const arbor::accel::KernelTable* ARBOR_KERNEL_ENTRY() { return &table; }
