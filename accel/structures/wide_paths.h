#pragma once
/// The BVHs' SIMD paths (TracePath::single and TracePath::packet) over an N-wide layout collapsed
/// from their BinaryBvh (wide/wide_layout.h): WideBvhAccel<N> (wide_paths_impl.h) is a BvhAccel with
/// that layout, one class per width, each width in its own translation unit
/// (wide_paths{4,8,16}.cpp). This header is the light part: a kernel set's own widths and factory
/// (defined in wide_paths.cpp, compiled once per kernel set). The rest of arbor reaches them through
/// the kernel set in use (dispatch/kernel_entries.h).
#include "accel/interface/accel.h"
#include "accel/bvh/binary_bvh.h"

#include <memory>

namespace arbor::accel::kset {

/// The width used when none is asked for, the measured best of the kernel set: 16 with AVX-512,
/// 8 with AVX2, 4 with SSE4.2 only.
std::uint32_t default_wide_width();
/// Widths the kernel set can trace: 4 always, 8 with AVX2, 16 with AVX-512.
bool wide_width_supported(std::uint32_t width);
/// The BVH over `bvh` (built over `tris`) with the SIMD layout of width cfg.wide.width (0 or
/// unsupported: the default) and, when cfg.layouts asks for it, the scalar layout too.
std::unique_ptr<Accel> make_wide_bvh_accel(AccelKind kind, const BinaryBvh& bvh, const TriangleView& tris,
                                           const BuildConfig& cfg, double build_ms);

/// The compact mode's BVH (BuildConfig::compact; structures/compact_paths.cpp) of width `width`
/// (supported by the kernel set).
std::unique_ptr<Accel> make_compact_bvh_accel(std::uint32_t width, AccelKind kind, const BinaryBvh& bvh,
                                              const TriangleView& tris, const BuildConfig& cfg, double build_ms);

}  // namespace arbor::accel::kset
