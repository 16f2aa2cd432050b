// The renderer on the fast paths: camera and shadow batches go to the packet path and bounce
// batches to the single-ray SIMD path of the BVHs; the images are bit-identical with brute force's
// (the oracle) and with 1 and 2 threads on those paths too.
#include "accel/factory/make_accel.h"
#include "accel/interface/accel.h"
#include "engine/tracer.h"
#include "render_scenes.h"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>

using namespace arbor;
using engine::IntegratorKind;
using engine::RenderRayKind;

namespace {

engine::Image render_with(const accel::Accel& a, const engine::Scene& s, const engine::RenderSettings& set,
                          int threads, engine::RenderStats* stats = nullptr) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    return engine::render(s, a, set, stats);
}

/// small_scene with an emissive quad, so that every ray kind is traced.
engine::Scene lit_scene() {
    auto s = testing::small_scene();
    s.mesh.append(engine::with_material(engine::make_ground(2.5f, 0.0f, 0.0f, 0.4f), testing::emitter(5.0f)));
    s.mesh.compute_bounds();
    return s;
}

}  // namespace

TEST_CASE("tracer: camera and shadow rays take the packet path, bounces the single-ray path, on the BVHs and the kd-tree") {
    const auto s = lit_scene();
    // The path the policy gives a renderer batch of kind k (no rays needed: the hint decides).
    const auto path_for = [](const accel::Accel& a, RenderRayKind k) {
        return accel::choose_path(a.offer(), {}, {accel::Query::closest, accel::TracePath::best, engine::ray_hint(k)}).path;
    };
    for (accel::AccelKind k : {accel::AccelKind::bvh_sah, accel::AccelKind::bvh_median, accel::AccelKind::lbvh}) {
        const auto a = accel::make_accel(k, s.mesh.view());
        CAPTURE(accel::to_string(k));
        REQUIRE(a->offer().has(accel::TracePath::packet));
        REQUIRE(a->offer().has(accel::TracePath::single));
        CHECK(path_for(*a, RenderRayKind::primary) == accel::TracePath::packet);
        CHECK(path_for(*a, RenderRayKind::shadow) == accel::TracePath::packet);
        CHECK(path_for(*a, RenderRayKind::mirror) == accel::TracePath::single);
        CHECK(path_for(*a, RenderRayKind::diffuse) == accel::TracePath::single);
        CHECK(path_for(*a, RenderRayKind::ao) == accel::TracePath::single);
    }
    // The kd-tree's packet walk pays on coherent rays too (primary and shadow rays ~1.9x its
    // single path on the held-out rays): the same choices. Brute force has only the scalar path.
    const auto kd = accel::make_accel(accel::AccelKind::kdtree, s.mesh.view());
    CHECK(path_for(*kd, RenderRayKind::primary) == accel::TracePath::packet);
    CHECK(path_for(*kd, RenderRayKind::shadow) == accel::TracePath::packet);
    CHECK(path_for(*kd, RenderRayKind::diffuse) == accel::TracePath::single);
    const auto brute = accel::make_accel(accel::AccelKind::brute, s.mesh.view());
    CHECK(path_for(*brute, RenderRayKind::primary) == accel::TracePath::scalar);
}

TEST_CASE("render on the BVH fast paths: same image as brute force, same with 1 and 2 threads") {
    const auto s = lit_scene();
    const auto brute = accel::make_accel(accel::AccelKind::brute, s.mesh.view());
    const auto bvh = accel::make_accel(accel::AccelKind::bvh_sah, s.mesh.view());
    for (IntegratorKind k : {IntegratorKind::primary, IntegratorKind::ao, IntegratorKind::direct, IntegratorKind::path}) {
        CAPTURE(engine::to_string(k));
        auto set = testing::tiny_settings(k, 32, 24, 2);
        set.layers = engine::Layers{true, true, true};
        engine::RenderStats st_brute, st_bvh;
        const auto ref = render_with(*brute, s, set, 2, &st_brute);
        const auto one = render_with(*bvh, s, set, 1);
        const auto two = render_with(*bvh, s, set, 2, &st_bvh);
        REQUIRE(one.names == two.names);
        for (std::size_t c = 0; c < one.planes.size(); ++c) CHECK(one.planes[c] == two.planes[c]);
        // Every path returns brute force's closest-hit record bit for bit (one watertight test, one
        // tie rule: accel/core/hit_record.h) and the renderer reads only hit/miss of any-hit
        // answers, so the images are identical in every layer, bit for bit.
        REQUIRE(ref.names == two.names);
        std::size_t differing = 0;
        for (std::size_t c = 0; c < ref.planes.size(); ++c)
            for (std::size_t i = 0; i < ref.planes[c].size(); ++i)
                differing += std::memcmp(&ref.planes[c][i], &two.planes[c][i], sizeof(float)) != 0;
        CAPTURE(differing);
        CHECK(differing == 0);
        CHECK(st_bvh.count(RenderRayKind::primary) == st_brute.count(RenderRayKind::primary));
        CHECK(st_bvh.total() > 0);
    }
}
