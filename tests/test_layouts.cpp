// BuildConfig::layouts: a structure built with only the scalar layout or only the SIMD layouts
// says so through offer(), traces a path whose layout is missing on one it has (same answers as
// brute), and the statistics mode needs the scalar layout.
#include "accel/dispatch/kernel_entries.h"
#include "accel/factory/make_accel.h"
#include "accel/structures/brute_accel.h"
#include "accel/structures/bvh_accel.h"
#include "accel/structures/wide_paths.h"
#include "engine/procedural.h"
#include "testing.h"

#include <doctest/doctest.h>

using namespace arbor;
using accel::Layouts;
using accel::TracePath;

TEST_CASE("layouts: only the asked-for traversal layouts are built, every path still answers") {
    const engine::Mesh mesh = engine::make_icosphere({0.0f, 0.0f, 0.0f}, 1.0f, 3, 0.02f, 11);
    const accel::TriangleView view = mesh.view();
    const accel::BruteAccel brute(view);
    const auto rays = testing::random_rays_into(mesh.bounds, 600, 5);
    std::vector<accel::Hit> ref(rays.size()), ref_any(rays.size());
    brute.trace(rays, ref, {accel::Query::closest, TracePath::scalar});
    for (const auto kind : {accel::AccelKind::bvh_median, accel::AccelKind::bvh_sah, accel::AccelKind::lbvh, accel::AccelKind::kdtree}) {
        accel::BuildConfig all_cfg;
        const auto all = accel::make_accel(kind, view, all_cfg);
        for (const Layouts layouts : {Layouts::scalar, Layouts::simd}) {
            CAPTURE(accel::to_string(kind));
            CAPTURE(int(layouts));
            accel::BuildConfig cfg;
            cfg.layouts = layouts;
            const auto a = accel::make_accel(kind, view, cfg);
            const bool simd = layouts == Layouts::simd;
            CHECK(a->offer().has(TracePath::packet) == simd);
            CHECK(a->offer().has(TracePath::single) == simd);
            // The kd-tree's scalar walk reads the tree every path shares; a BVH's reads its own layout.
            CHECK(a->offer().has(TracePath::scalar) == (!simd || kind == accel::AccelKind::kdtree));
            if (simd && kind == accel::AccelKind::kdtree) CHECK(a->stats().memory_bytes == all->stats().memory_bytes);
            else CHECK(a->stats().memory_bytes < all->stats().memory_bytes);
            // A SIMD-only BVH build stops at leaves of the layout's width (test_leaf_floor.cpp): fewer
            // nodes where that width is above the leaf size (4-wide, the sse4 kernel set's widest, equal
            // to it: no more nodes, and fewer only where SAH would have split a range of 4).
            if (!simd || kind == accel::AccelKind::kdtree) CHECK(a->stats().sah_cost == all->stats().sah_cost);
            else if (accel::default_wide_width() > cfg.bvh.max_leaf_size) CHECK(a->stats().nodes < all->stats().nodes);
            else CHECK(a->stats().nodes <= all->stats().nodes);
            const TracePath best = accel::choose_path(a->offer(), rays, {}).path;
            CHECK(a->offer().has(best));
            if (!simd) CHECK(best == TracePath::scalar);
            for (const TracePath p : {TracePath::best, TracePath::scalar, TracePath::packet, TracePath::single}) {
                CAPTURE(accel::to_string(p));
                std::vector<accel::Hit> got(rays.size()), any(rays.size());
                a->trace(rays, got, {accel::Query::closest, p});
                a->trace(rays, any, {accel::Query::any, p});
                CHECK(testing::count_disagreements(got, ref) == 0);
                CHECK(testing::count_occlusion_disagreements(any, ref) == 0);
            }
            std::vector<accel::Hit> counted(rays.size());
            accel::TraceCounters counters;
            // The counted mode needs the scalar layout: offered with it, refused (logic_error) without.
            CHECK(a->offer().counts == a->offer().has(TracePath::scalar));
            if (a->offer().counts) CHECK_NOTHROW(a->trace(rays, counted, {accel::Query::closest, TracePath::best, {}, {}, &counters}));
            else CHECK_THROWS_AS(a->trace(rays, counted, {accel::Query::closest, TracePath::best, {}, {}, &counters}), std::logic_error);
        }
    }
}
