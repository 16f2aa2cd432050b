// The counted single-ray walk (WideBvhAccel::trace_counted, which `arbor-bench limit count` reads):
// its hits are TracePath::single's bit for bit (closest and any), at every width of the build and
// for the kd-tree's cell paths too; its counts are plausible: a ray that misses the root's children
// tests one node and no block, a ray no path traces tests nothing, each block tested holds 1 to N
// triangles, and a ray that hits tested at least one block.
#include "accel/structures/bvh_accel.h"
#include "accel/structures/kdtree_accel.h"
#include "accel/structures/wide_paths_impl.h"
#include "testing.h"
#include "wide_bvh.h"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <vector>

using namespace arbor;
using accel::Hit;
using accel::Ray;

namespace {

template <std::size_t N>
void check_counted(const accel::WideBvhAccel<N>& w, const accel::Accel& traced, const accel::Bounds& b,
                   const std::vector<Ray>& rays) {
    for (const accel::Query q : {accel::Query::closest, accel::Query::any}) {
        CAPTURE(N);
        CAPTURE(int(q));
        std::vector<Hit> counted(rays.size()), single(rays.size());
        accel::WideCounts c;
        w.trace_counted(rays, counted, q, c);
        traced.trace(rays, single, {q, accel::TracePath::single});
        std::size_t differ = 0, hits = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            differ += std::memcmp(&counted[i], &single[i], sizeof(Hit)) != 0;
            hits += counted[i].is_hit();
        }
        CHECK(differ == 0);
        CHECK(hits > rays.size() / 4);
        CHECK(c.rays == rays.size());
        CHECK(c.node_tests >= hits);
        CHECK(c.blocks >= hits);
        CHECK(c.triangles >= c.blocks);
        CHECK(c.triangles <= c.blocks * N);

        // One ray at a time: each hit tested a block; a ray away from the scene, one node and no block.
        for (std::size_t i = 0; i < rays.size(); i += 97) {
            accel::WideCounts one;
            Hit h;
            w.trace_counted({&rays[i], 1}, {&h, 1}, q, one);
            CHECK(std::memcmp(&h, &single[i], sizeof(Hit)) == 0);
            CHECK(one.rays == 1);
            if (h.is_hit()) CHECK((one.node_tests >= 1 && one.blocks >= 1));
        }
    }
    const accel::Vec3f away = b.hi + b.extent();
    const Ray miss{away, 0.0f, {1.0f, 0.5f, 0.25f}, INFINITY};  // from beyond the box, outwards
    const Ray none{{NAN, 0.0f, 0.0f}, 0.0f, {1.0f, 0.0f, 0.0f}, INFINITY};
    for (const accel::Query q : {accel::Query::closest, accel::Query::any}) {
        accel::WideCounts c;
        Hit h[2];
        const Ray two[2] = {miss, none};
        w.trace_counted(two, h, q, c);
        CHECK(!h[0].is_hit());
        CHECK(!h[1].is_hit());
        CHECK(c.rays == 2);
        CHECK(c.node_tests == 1);
        CHECK(c.blocks == 0);
        CHECK(c.triangles == 0);
    }
}

template <std::size_t N>
void check_width(const engine::Mesh& mesh, const std::vector<Ray>& rays) {
    if constexpr (accel::wide_width_available<N>()) {
        const auto acc = testing::wide_bvh<N>(mesh.view());
        check_counted<N>(dynamic_cast<const accel::WideBvhAccel<N>&>(*acc), *acc, mesh.bounds, rays);
    }
}

}  // namespace

TEST_CASE("counted wide walk: the single path's hits bit for bit, plausible counts") {
    const engine::Mesh mesh = testing::procedural_shapes();
    const std::vector<Ray> rays = testing::three_kinds(mesh.bounds, 1500, 7);
    check_width<4>(mesh, rays);
    check_width<8>(mesh, rays);
    check_width<16>(mesh, rays);

    // The kd-tree's cells (its SIMD paths) and lbvh, at the width the build picks.
    for (const accel::AccelKind kind : {accel::AccelKind::kdtree, accel::AccelKind::lbvh}) {
        CAPTURE(int(kind));
        accel::BuildConfig cfg;
        cfg.layouts = accel::Layouts::simd;
        // The widest layout this file can name (a portable build compiles it without AVX-512 or
        // AVX2, while the kernel set it runs may have them).
        cfg.wide.width = XSIMD_WITH_AVX512F ? 16u : (XSIMD_WITH_AVX2 ? 8u : 4u);
        const auto acc = accel::make_accel(kind, mesh.view(), cfg);
        const accel::Accel* target = acc.get();
        if (const auto* kd = dynamic_cast<const accel::KdTreeAccel*>(target); kd && kd->cell_paths())
            target = kd->cell_paths();
        bool checked = false;
#if XSIMD_WITH_AVX512F
        if (const auto* w = dynamic_cast<const accel::WideBvhAccel<16>*>(target))
            check_counted<16>(*w, *acc, mesh.bounds, rays), checked = true;
#endif
#if XSIMD_WITH_AVX2
        if (const auto* w = dynamic_cast<const accel::WideBvhAccel<8>*>(target))
            check_counted<8>(*w, *acc, mesh.bounds, rays), checked = true;
#endif
        if (const auto* w = dynamic_cast<const accel::WideBvhAccel<4>*>(target))
            check_counted<4>(*w, *acc, mesh.bounds, rays), checked = true;
        CHECK(checked);
    }
}
