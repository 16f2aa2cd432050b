#pragma once
/// The factory: builds any structure and makes the Accel its layouts need, through the kernel set
/// in use for the SIMD layouts (dispatch/). The one place that knows every structure; the path
/// policy and the structures below it know none of the others.
#include "accel/bvh/binary_bvh.h"
#include "accel/interface/accel.h"
#include "accel/kdtree/kdtree_node.h"
#include "accel/structures/bvh_accel.h"
#include "accel/structures/kdtree_accel.h"

#include <memory>
#include <string>
#include <vector>

namespace arbor::accel {

/// Builds structure `kind` over `tris`. The view must outlive the Accel only for `brute`
/// (the others copy what they need). `automatic` is resolved by the caller (select/auto_select.h).
/// With cfg.max_memory set, a build whose estimate (memory_estimate.h) exceeds it throws
/// MemoryLimitError before anything is allocated.
std::unique_ptr<Accel> make_accel(AccelKind kind, const TriangleView& tris, const BuildConfig& cfg = {});

/// What a build of `kind` with `cfg` will offer, as far as the path policy reads it (paths and
/// queries, counts, packets_pay, simd_skipped), known before building, as each structure reports
/// it: --accel auto asks the policy with it which path a structure would take for a hint (tests
/// check it against the structures' own offer()).
PathOffer expected_offer(AccelKind kind, const BuildConfig& cfg);

/// What a build of `kind` with `cfg` leaves out, one item per line, as each structure reports it:
/// the layouts not built, and for a BVH built for the SIMD paths only the binary splits below its
/// leaf floor.
std::vector<std::string> skipped_by_build(AccelKind kind, const BuildConfig& cfg);

/// The Accel for any BinaryBvh: BvhAccel for a build of the scalar layout only, else
/// WideBvhAccel<cfg.wide.width> of the kernel set in use (structures/wide_paths.h).
std::unique_ptr<Accel> make_bvh_accel(AccelKind kind, BinaryBvh&& bvh, const TriangleView& tris,
                                      const BuildConfig& cfg, double build_ms);

/// The BvhBuildConfig::leaf_floor a BVH build with `cfg` gets: for builds of the SIMD layouts
/// only, cfg.bvh.simd_leaf_floor with 0 read as the SIMD layout's width; else 0 (no floor).
std::uint32_t bvh_leaf_floor(const BuildConfig& cfg);

/// BuildPrims straight from the triangles -> `builder` -> the Accel, timed as a whole (build_ms
/// covers all three steps); the builder sees cfg.bvh with leaf_floor = bvh_leaf_floor(cfg), and
/// the build prims are freed before the layouts are made.
std::unique_ptr<Accel> build_bvh_accel(AccelKind kind, const TriangleView& tris, const BuildConfig& cfg,
                                       BvhPrimBuilder builder);

/// Builds the kd-tree over `tris` (copies what it needs; the view may go away afterwards) with its
/// SIMD paths when cfg.layouts asks for them.
std::unique_ptr<KdTreeAccel> make_kdtree_accel(const TriangleView& tris, const BuildConfig& cfg = {});
/// The same over a tree built before (`build_ms`: its build time; the SIMD layouts' time is added).
std::unique_ptr<KdTreeAccel> make_kdtree_accel(KdTree tree, const BuildConfig& cfg, double build_ms = 0.0);

}  // namespace arbor::accel
