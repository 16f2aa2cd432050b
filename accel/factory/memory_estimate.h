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
/// brute: exact. bvh-median, bvh-sah, lbvh: an upper bound for every leaf size and SIMD width (the
/// worst case is one triangle per leaf: 2N - 1 nodes in the binary tree, the scalar layout and the
/// wide layout alive together; about 300 bytes per triangle measured, 384 + 64 KiB bounded). kdtree:
/// a lower bound (prim refs and the first events); its builder checks as it grows, because split
/// clipping duplicates references by an amount only the build finds out.
std::uint64_t build_memory_estimate(AccelKind kind, std::size_t triangles, const BuildConfig& cfg);

/// Throws MemoryLimitError when cfg.max_memory is set and build_memory_estimate exceeds it.
void check_build_memory(AccelKind kind, std::size_t triangles, const BuildConfig& cfg);

}  // namespace arbor::accel
