#include "accel/structures/bvh_accel.h"

#include "accel/bvh/bvh2_queries.h"
#include "accel/bvh/bvh2_refit.h"
#include "accel/bvh/bvh2_traverse.h"
#include "accel/bvh/bvh2_winding.h"
#include "accel/core/hit_record.h"
#include "accel/core/memory_limit.h"
#include "accel/util/timer.h"
#include "simd/ray_triangle.h"

#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <exception>
#include <string>
#include <vector>

namespace arbor::accel {

BvhAccel::BvhAccel(AccelKind kind, const BinaryBvh& bvh, const TriangleView& tris, const BuildConfig& cfg, double build_ms)
    : Accel(kind) {
    init(bvh, tris, cfg, build_ms, {});
}

void BvhAccel::init(const BinaryBvh& bvh, const TriangleView& tris, const BuildConfig& cfg, double build_ms,
                    const std::function<WideShape(const WideConfig& wide)>& make_wide) {
    const Timer timer;
    const bool scalar = cfg.layouts != Layouts::simd;
    // While converting, the binary tree, the layouts and the converter's three words per node live
    // together (the peak worked out below): with a limit, the layouts are checked before they are
    // made, the scalar one from the tree alone, the SIMD one from its plan (WideConfig::max_bytes).
    const std::size_t tree_bytes = conversion_held_bytes(bvh);
    WideConfig wide = cfg.wide;
    const std::string limit = cfg.max_memory != 0 ? max_memory_text(cfg.max_memory) : std::string();
    if (cfg.max_memory != 0) {
        check_binary_peak(kind(), bvh, cfg.max_memory);
        const std::uint64_t held = tree_bytes + (scalar ? bvh2_layout_bytes(bvh) : 0);
        // (A SIMD layout takes some bytes: with one to make, the limit must leave room.)
        if (held > cfg.max_memory || (make_wide && held == cfg.max_memory))
            throw MemoryLimitError(std::string(to_string(kind())) + ": its binary tree and scalar layout need " +
                                   mib_text(held) + ", more than " + limit);
        wide.max_bytes = cfg.max_memory - held;
    }
    BvhTreeStats tree;
    // The layouts and the statistics only read the binary tree: made side by side. The SIMD
    // layout, the biggest, on the calling thread: made on a TBB worker, its arrays came from that
    // worker's malloc arena, with 2.8x the page faults (4.4M triangles: 26k instead of 9.4k).
    tbb::task_group side;
    side.run([&] { if (scalar) layout_ = make_bvh2_layout(bvh, tris); });
    side.run([&] { tree = bvh_tree_stats(bvh, cfg.bvh.traversal_cost, cfg.bvh.intersection_cost); });
    std::exception_ptr failed;  // (the side tasks end first: they read the tree the caller frees)
    if (make_wide) {
        try {
            wide_ = make_wide(wide);
        } catch (const MemoryLimitError& e) {
            failed = std::make_exception_ptr(
                MemoryLimitError(std::string(to_string(kind())) + ": " + e.what() + " of " + limit));
        } catch (...) {
            failed = std::current_exception();
        }
    }
    side.wait();
    if (failed) std::rethrow_exception(failed);
    stats_.triangles = tris.triangle_count();
    stats_.dropped_nonfinite = bvh.dropped_nonfinite;
    stats_.nodes = tree.nodes;
    stats_.leaves = tree.leaves;
    stats_.max_depth = tree.max_depth;
    stats_.mean_leaf_depth = tree.mean_leaf_depth;
    stats_.sah_cost = tree.sah_cost;
    // Both layouts: the scalar reference path and the SIMD paths.
    stats_.memory_bytes = (scalar ? layout_.memory_bytes() : 0) + wide_.memory_bytes;
    const std::size_t convert_peak = tree_bytes + stats_.memory_bytes;
    stats_.build_peak_bytes = std::max(bvh.build_peak_bytes, convert_peak);
    stats_.build_ms = build_ms + timer.ms();
    if (scalar) offer_.add(TracePath::scalar);
    offer_.counts = scalar;
    offer_.simd_skipped = !make_wide;
    if (!bvh.nodes.empty()) offer_.scene_diagonal = simd::length(bvh.nodes[0].box.extent());
    if (scalar) built_sah_ = bvh2_sah_cost(layout_);
}

std::string_view BvhAccel::refit_unsupported() const {
    if (kind_ == AccelKind::kdtree) return "a kd-tree's cells cannot be refit: their boxes are the cells' split planes";
    return {};
}

double BvhAccel::refit_layouts(const TriangleView& tris, Bounds& bounds) {
    if (layout_.empty()) return 0.0;
    const double cost = refit_bvh2_layout(layout_, tris);
    bounds = layout_.root_box;
    return cost;
}

RefitResult BvhAccel::refit(const TriangleView& tris) {
    if (!refit_unsupported().empty()) return Accel::refit(tris);
    const Timer timer;
    RefitResult r;
    r.sah_cost = refit_layouts(tris, r.bounds);
    if (!r.bounds.empty()) offer_.scene_diagonal = simd::length(r.bounds.extent());
    r.built_sah_cost = built_sah_;
    r.ms = timer.ms();
    return r;
}

template <bool AnyHit, bool Count>
void BvhAccel::trace_batch(std::span<const Ray> rays, std::span<Hit> hits, TraceCounters* counters) const {
    std::uint64_t nodes = 0, tests = 0;
    std::array<Bvh2StackEntry, 64> small;
    std::vector<Bvh2StackEntry> large;
    std::span<Bvh2StackEntry> stack(small);
    if (bvh2_stack_size(layout_) > small.size()) {
        large.resize(bvh2_stack_size(layout_));
        stack = large;
    }
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Ray& ray = rays[i];
        HitRecord<AnyHit> best;
        if (ray_is_traceable(ray)) {
            const simd::WoopShear shear = simd::woop_shear(ray.dir);
            float tfar = ray.tfar;
            auto leaf = [&](std::uint32_t first, std::uint32_t count) {
                if constexpr (Count) ++nodes;
                bool found = false;
                for (std::uint32_t s = first; s < first + count; ++s) {
                    if constexpr (Count) ++tests;
                    const TriBlock4& b = layout_.blocks[s / tri_block_width];
                    const std::uint32_t l = s % tri_block_width;
                    const simd::TriHit<float> h = simd::woop_test(
                        ray.org, shear, ray.tnear, tfar, {b.v0[0][l], b.v0[1][l], b.v0[2][l]},
                        {b.v1[0][l], b.v1[1][l], b.v1[2][l]}, {b.v2[0][l], b.v2[1][l], b.v2[2][l]});
                    if (h.hit && best.offer(h.t, layout_.prim_ids[s], h.u, h.v)) {
                        tfar = h.t;
                        found = true;
                        if constexpr (AnyHit) return true;
                    }
                }
                return found;
            };
            if constexpr (Count) traverse_bvh2<AnyHit>(layout_, ray.org, ray.dir, ray.tnear, tfar, stack, leaf, [&] { ++nodes; });
            else traverse_bvh2<AnyHit>(layout_, ray.org, ray.dir, ray.tnear, tfar, stack, leaf);
        }
        hits[i] = best.hit;
    }
    if constexpr (Count) {
        counters->rays += rays.size();
        counters->nodes_visited += nodes;
        counters->triangles_tested += tests;
    }
}

Hit BvhAccel::trace_one(const Ray& ray, Query query) const {
    Hit h;
    run_scalar({&ray, 1}, {&h, 1}, query, nullptr);
    return h;
}

void BvhAccel::run(std::span<const Ray> rays, std::span<Hit> hits, Query query, TracePath, TraceCounters* counters) const {
    run_scalar(rays, hits, query, counters);
}

void BvhAccel::trace_all(std::span<const Ray> rays, HitSink& sink) const {
    std::vector<Bvh2StackEntry> stack(bvh2_stack_size(layout_));
    std::vector<Hit> hits;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        hits.clear();
        if (ray_is_traceable(rays[i])) all_hits_bvh2(layout_, rays[i], stack, hits);
        sort_unique_hits(hits);
        sink.take(i, hits);
    }
}

void BvhAccel::closest_points(std::span<const Vec3f> points, float max_distance, std::span<PointHit> out) const {
    std::vector<Bvh2StackEntry> stack;
    for (std::size_t i = 0; i < points.size(); ++i) {
        PointSearch s(points[i], max_distance);
        closest_point_bvh2(layout_, s, stack);
        out[i] = s.result();
    }
}

void BvhAccel::run_scalar(std::span<const Ray> rays, std::span<Hit> hits, Query query, TraceCounters* counters) const {
    const bool any_hit = query == Query::any;
    if (counters) {
        if (any_hit) trace_batch<true, true>(rays, hits, counters);
        else trace_batch<false, true>(rays, hits, counters);
    } else if (any_hit) {
        trace_batch<true>(rays, hits);
    } else {
        trace_batch<false>(rays, hits);
    }
}

std::size_t conversion_held_bytes(const BinaryBvh& bvh) {
    return bvh.nodes.capacity() * sizeof(BvhBuildNode) + bvh.prim_ids.capacity() * sizeof(std::uint32_t) +
           bvh.nodes.size() * 3 * sizeof(std::uint32_t);
}

void check_binary_peak(AccelKind kind, const BinaryBvh& bvh, std::uint64_t max_memory) {
    if (max_memory != 0 && bvh.build_peak_bytes > max_memory)
        throw MemoryLimitError(std::string(to_string(kind)) + ": building its binary tree reached " +
                               mib_text(bvh.build_peak_bytes) + ", more than " + max_memory_text(max_memory));
}

PathOffer bvh_offer(const BuildConfig& cfg) {
    PathOffer o;
    if (cfg.compact) {  // (the compact layout: `single` and `packet`, structures/compact_paths.cpp)
        o.add(TracePath::single), o.add(TracePath::packet), o.packets_pay = true;
        return o;
    }
    const bool simd = cfg.layouts != Layouts::scalar, scalar = cfg.layouts != Layouts::simd;
    if (scalar) o.add(TracePath::scalar);
    o.counts = scalar, o.simd_skipped = !simd;
    if (simd) o.add(TracePath::single), o.add(TracePath::packet), o.packets_pay = true;
    return o;
}

std::vector<std::string> bvh_skipped(const BuildConfig& cfg, std::uint32_t leaf_floor) {
    std::vector<std::string> out;
    if (cfg.compact)
        out.push_back("scalar layout (compact mode traces the SIMD paths only)");
    else if (cfg.layouts == Layouts::scalar)
        out.push_back("SIMD layouts (only the SIMD paths read them)");
    else if (cfg.layouts == Layouts::simd)
        out.push_back("scalar layout (only the scalar path reads it)");
    // A BVH built for the SIMD paths only stops splitting at the layout's width.
    if (leaf_floor > 1)
        out.push_back("binary splits of ranges of at most " + std::to_string(leaf_floor) +
                      " triangles (the SIMD leaves' blocks hold them; --simd-leaf-floor 1 makes them)");
    return out;
}

std::unique_ptr<WindingTree> BvhAccel::make_winding_tree(const TriangleView&) const {
    return make_bvh2_winding(layout_);
}

}  // namespace arbor::accel
