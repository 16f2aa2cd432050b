#pragma once
/// Build memory before building: BuildConfig::max_memory is checked against an estimate from the
/// triangle count before any allocation, and MemoryLimitError says which structure and how much.
#include "accel/core/memory_limit.h"
#include "accel/interface/accel.h"

#include <cstdint>
#include <stdexcept>

namespace arbor::accel {

/// Bytes building `kind` over `triangles` triangles takes at its peak (the structure kept plus the
/// temporaries alive with it; the caller's TriangleView not counted), from the triangle count alone.
/// brute: exact. bvh-median, bvh-sah, lbvh: 384 bytes per triangle + 64 KiB, above the measured
/// peak of every leaf size and SIMD width with the SIMD layout's leaf floor (about 70-115 bytes per
/// triangle on large meshes, up to about 300 on small ones, where fixed sizes weigh). Not a bound
/// for a finer tree: with --simd-leaf-floor 1 a SIMD layout of one-triangle leaves takes a whole
/// block each (over 500 bytes per triangle measured, 16 wide); so the BVHs also check their
/// layouts, from their exact sizes, before making them (BvhAccel::init, WideConfig::max_bytes).
/// kdtree: a lower bound (prim refs and the first events); its builder checks as it grows, because
/// split clipping duplicates references by an amount only the build finds out.
std::uint64_t build_memory_estimate(AccelKind kind, std::size_t triangles, const BuildConfig& cfg);

/// Throws MemoryLimitError when cfg.max_memory is set and build_memory_estimate exceeds it.
void check_build_memory(AccelKind kind, std::size_t triangles, const BuildConfig& cfg);

}  // namespace arbor::accel
