#pragma once
/// KdSimdAccel<N>: the kd-tree with its SIMD paths (TracePath::single and TracePath::packet) and
/// its leaves' triangles in SIMD blocks of N (kdtree_blocks.h), defined in kdtree_simd.cpp. Any
/// hit: both paths visit, for every ray, exactly the leaves of the scalar path's stack walk
/// (kdtree_stack.h; the packet path in its packet form, kdtree_stack_packet.h), in the same order,
/// and take the first hit in that order. Closest hit: `single` follows the scalar path's ropes
/// (kdtree_traverse.h), `packet` the stack walk; both walks offer every triangle that can be the
/// closest hit, with the same rule (the smallest t, on equal t the lowest prim). So the answers
/// are bit-identical to the scalar path's.
#include "accel/structures/kdtree_accel.h"

#include <memory>

namespace arbor::accel::kset {

/// A kernel set's own entries (defined in kdtree_simd.cpp, compiled once per kernel set); the rest
/// of arbor reaches them through the kernel set in use (dispatch/kernel_entries.h).
/// Block width when none is asked for: 8, or 4 with SSE4.2 only.
std::uint32_t default_kd_block_width();

/// The kd-tree over `tree` with blocks of cfg.kd_blocks.width triangles (0 or unsupported: the
/// default; 16 needs AVX-512, 8 AVX2), packets of cfg.packets.lanes rays (0: the kernel set's
/// widest, 16 with AVX-512, 8 with AVX2, 4 with SSE4.2 only), leaves reached by at
/// most cfg.packets.switch_lanes lanes of a packet (-1: lanes / 8) tested one lane at a time.
std::unique_ptr<KdTreeAccel> make_kd_simd_accel(KdTree tree, const BuildConfig& cfg, double build_ms);

}  // namespace arbor::accel::kset
