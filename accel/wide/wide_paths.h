#pragma once
/// The BVHs' SIMD paths (TracePath::single and TracePath::packet) over an N-wide layout collapsed
/// from their BinaryBvh (wide_layout.h): WideBvhAccel<N> (wide_paths_impl.h) is a BvhAccel with
/// that layout, one class per width, each width in its own translation unit
/// (wide_paths{4,8,16}.cpp). This header is the light part: widths and the factory.
#include "accel/accel.h"
#include "accel/bvh/binary_bvh.h"

#include <memory>

namespace arbor::accel {

/// The width used when none is asked for: the measured best of this build (perf/results/wide-*.md).
std::uint32_t default_wide_width();
/// Widths this build can trace: 4 and 8 always (x86-64-v3 or better), 16 with AVX-512.
bool wide_width_supported(std::uint32_t width);
/// The width a layout asked for `width` gets: `width` when supported, else default_wide_width().
std::uint32_t wide_width_or_default(std::uint32_t width);

/// The BVH over `bvh` (built over `tris`) with the SIMD layout of width cfg.bvh_width (0 or
/// unsupported: the default) and, when cfg.layouts asks for it, the scalar layout too.
std::unique_ptr<Accel> make_wide_bvh_accel(AccelKind kind, const BinaryBvh& bvh, const TriangleView& tris,
                                           const BuildConfig& cfg, double build_ms);

}  // namespace arbor::accel
