#pragma once
/// KdSimdAccel<N>: the kd-tree with its SIMD paths (TracePath::single and TracePath::packet) over
/// its rope walk (kdtree_traverse.h) and its leaves' triangles in SIMD blocks of N
/// (kdtree_blocks.h), defined in kdtree_simd.cpp. Both paths visit, for every ray, exactly the
/// leaves the scalar walk visits, in the same order, and keep the scalar path's hit rule
/// (closest: the smallest t, on equal t the lowest prim; any hit: the first hit in walk order), so
/// their answers are bit-identical to the scalar path's.
#include "accel/kdtree/kdtree_accel.h"

#include <memory>

namespace arbor::accel {

/// Block width when none is asked for (perf/results/kdtree-simd-*.md).
std::uint32_t default_kd_block_width();

/// The kd-tree over `tree` with blocks of cfg.kd_block_width triangles (0 or unsupported: the
/// default), packets of cfg.packet_lanes rays (0: 16 with AVX-512, else 8), leaves reached by at
/// most cfg.packet_switch lanes of a packet (-1: lanes / 8) tested one lane at a time.
std::unique_ptr<KdTreeAccel> make_kd_simd_accel(KdTree tree, const BuildConfig& cfg, double build_ms);

}  // namespace arbor::accel
