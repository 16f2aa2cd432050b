#pragma once
/// KernelTable: the entry points of one SIMD kernel set (the structures' SIMD paths: the wide
/// BVHs (structures/wide_paths.h) and the kd-tree's blocks (structures/kdtree_simd.h), whose
/// `kset` functions each set defines), which the rest of arbor
/// reaches only through the table of the set in use (kernel_set.h). A native build holds one set,
/// compiled for its -march; a portable build (-DARBOR_PORTABLE=ON) holds three, sse4, avx2 and
/// avx512, each compiled from the same sources with its own flags and made into one object whose
/// only global symbol is its entry, so that no inline function or template of one set can stand in
/// for another's (cmake/ArborKernelSets.cmake says more).
#include "accel/structures/kdtree_simd.h"
#include "accel/structures/wide_paths.h"

#include <cstdint>
#include <memory>

namespace arbor::accel {

struct KernelTable {
    const char* name;  ///< "avx512", "avx2" or "sse4"
    std::uint32_t (*default_wide_width)();
    bool (*wide_width_supported)(std::uint32_t width);
    std::unique_ptr<Accel> (*make_wide_bvh_accel)(AccelKind kind, const BinaryBvh& bvh, const TriangleView& tris,
                                                  const BuildConfig& cfg, double build_ms);
    std::uint32_t (*default_kd_block_width)();
    std::unique_ptr<KdTreeAccel> (*make_kd_simd_accel)(KdTree tree, const BuildConfig& cfg, double build_ms);
};


}  // namespace arbor::accel

/// The entry of each kernel set (kernel_table.cpp, compiled once per set): its table.
extern "C" {
const arbor::accel::KernelTable* arbor_kernels_native();
const arbor::accel::KernelTable* arbor_kernels_sse4();
const arbor::accel::KernelTable* arbor_kernels_avx2();
const arbor::accel::KernelTable* arbor_kernels_avx512();
}
