#pragma once
/// The structures' SIMD entries routed to the kernel set in use (kernel_set.h): the same names as
/// each set's own `kset` functions (structures/wide_paths.h, structures/kdtree_simd.h), called
/// through that set's table (kernel_table.h). Everything above the structures calls these.
#include "accel/structures/kdtree_simd.h"
#include "accel/structures/wide_paths.h"

#include <cstdint>
#include <memory>

namespace arbor::accel {

/// The width used when none is asked for: 16 with AVX-512, 8 with AVX2, 4 with SSE4.2 only.
std::uint32_t default_wide_width();
/// Widths the kernel set in use can trace: 4 always, 8 with AVX2, 16 with AVX-512.
bool wide_width_supported(std::uint32_t width);
/// The width a layout asked for `width` gets: `width` when supported, else default_wide_width().
std::uint32_t wide_width_or_default(std::uint32_t width);
/// kset::make_wide_bvh_accel of the kernel set in use.
std::unique_ptr<Accel> make_wide_bvh_accel(AccelKind kind, const BinaryBvh& bvh, const TriangleView& tris,
                                           const BuildConfig& cfg, double build_ms);
/// kset::default_kd_block_width of the kernel set in use: 8, or 4 with SSE4.2 only.
std::uint32_t default_kd_block_width();
/// kset::make_kd_simd_accel of the kernel set in use.
std::unique_ptr<KdTreeAccel> make_kd_simd_accel(KdTree tree, const BuildConfig& cfg, double build_ms);

}  // namespace arbor::accel
