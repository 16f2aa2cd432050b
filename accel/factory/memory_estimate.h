#pragma once
/// Build memory before building: what a whole build may take, for planning (the renderer's budget),
/// and what BuildConfig::max_memory is checked against before a build starts, both from the
/// triangle count; MemoryLimitError says which structure and how much.
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
/// block each (over 500 bytes per triangle measured, 16 wide).
/// kdtree: a lower bound (prim refs and the first events); its builder checks as it grows, because
/// split clipping duplicates references by an amount only the build finds out.
std::uint64_t build_memory_estimate(AccelKind kind, std::size_t triangles, const BuildConfig& cfg);

/// The bytes check_build_memory compares with max_memory before a build starts. brute and kdtree:
/// build_memory_estimate. bvh-median, bvh-sah: what their build holds from its start, its
/// primitives and ids, 36 bytes per triangle + 64 KiB; their nodes are counted as the build makes
/// them, and the build stops as soon as the count passes the limit (BvhBuildConfig::max_bytes).
/// lbvh: its binary tree's build alone (its prims, nodes, ids, keys and sort), 208 bytes per
/// triangle + 64 KiB, above its measured peak (at most 180 bytes per triangle, with one triangle
/// per leaf). The layouts made from the tree are checked from their exact sizes before they are
/// made (BvhAccel::init), so a build is refused before it allocates more than the limit, not for
/// what a worst case could take.
std::uint64_t build_start_bytes(AccelKind kind, std::size_t triangles, const BuildConfig& cfg);

/// Throws MemoryLimitError when cfg.max_memory is set and build_start_bytes exceeds it.
void check_build_memory(AccelKind kind, std::size_t triangles, const BuildConfig& cfg);

}  // namespace arbor::accel
