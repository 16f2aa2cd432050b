#pragma once
/// KernelTable: the entry points of one SIMD kernel set (the structures' SIMD paths: the wide
/// BVHs of wide/ and the kd-tree's blocks of kdtree/kdtree_simd.cpp), which the rest of arbor
/// reaches only through the table of the set in use (kernel_set.h). A native build holds one set,
/// compiled for its -march; a portable build (-DARBOR_PORTABLE=ON) holds three, sse4, avx2 and
/// avx512, each compiled from the same sources with its own flags and made into one object whose
/// only global symbol is its entry, so that no inline function or template of one set can stand in
/// for another's (cmake/ArborKernelSets.cmake says more).
#include "accel/kdtree/kdtree_accel.h"
#include "accel/wide/wide_paths.h"

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

/// A kernel set's own definitions (wide/wide_paths.cpp, kdtree/kdtree_simd.cpp): the same names
/// in every set, each set's copy local to its object in a portable build. Callers go through
/// kernel_set.h's functions of the same names.
namespace kset {
std::uint32_t default_wide_width();
bool wide_width_supported(std::uint32_t width);
std::unique_ptr<Accel> make_wide_bvh_accel(AccelKind kind, const BinaryBvh& bvh, const TriangleView& tris,
                                           const BuildConfig& cfg, double build_ms);
std::uint32_t default_kd_block_width();
std::unique_ptr<KdTreeAccel> make_kd_simd_accel(KdTree tree, const BuildConfig& cfg, double build_ms);
}  // namespace kset

}  // namespace arbor::accel

/// The entry of each kernel set (kernel_table.cpp, compiled once per set): its table.
extern "C" {
const arbor::accel::KernelTable* arbor_kernels_native();
const arbor::accel::KernelTable* arbor_kernels_sse4();
const arbor::accel::KernelTable* arbor_kernels_avx2();
const arbor::accel::KernelTable* arbor_kernels_avx512();
}
