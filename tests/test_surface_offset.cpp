// Rays spawned from surfaces (accel/core/offset_ray.h) do not re-hit the triangle they leave, also when
// the hit point is near the origin on a huge triangle: the stadium floor (corners at +-1000, hit
// points at y = 0), whose 2^-16 offset alone re-hit the floor on ~7% of shadow and ~16% of diffuse
// rays (false hits at t ~ 0 that brute reported and box culling hid: structures then disagreed).
// Every structure and path agrees with brute on the stadium's shadow and diffuse rays.
#include "accel/factory/make_accel.h"
#include "accel/structures/brute_accel.h"
#include "accel/core/offset_ray.h"
#include "accel/interface/trace.h"
#include "engine/ray_gen.h"
#include "perf/scenes.h"
#include "testing.h"

#include <doctest/doctest.h>

#include <cmath>

using namespace arbor;
using accel::TracePath;

TEST_CASE("offset: 8 ulps of the triangle's scale along the normal, nothing for scale 0") {
    const accel::Vec3f p{0.0f, 0.0f, 0.0f}, n{0.0f, 1.0f, 0.0f};
    CHECK(accel::offset_ray_origin(p, n).y == doctest::Approx(1.0 / 65536.0));
    CHECK(accel::offset_ray_origin(p, n, 1000.0f).y == doctest::Approx(1.0 / 65536.0 + 1000.0 * std::ldexp(1.0, -21)));
    CHECK(accel::offset_ray_origin(p, n, 1000.0f).x == 0.0f);
    CHECK(accel::offset_ray_origin(p, n, INFINITY).y == doctest::Approx(1.0 / 65536.0));
    CHECK(accel::triangle_scale({1, -3, 2}, {0, 0, 0}, {-2.5f, 1, 1}) == 3.0f);
}

TEST_CASE("offset: stadium shadow and diffuse rays never re-hit the floor, and every structure and path agrees with brute") {
    const perf::BenchScene s = perf::teapot_in_stadium(nullptr);
    const accel::TriangleView view = s.scene.mesh.view();
    const accel::BruteAccel brute(view);
    const engine::RayGenScene gs = engine::ray_gen_scene(s.scene, s.use_scene_camera);
    const engine::PrimaryTracer tracer = [&](std::span<const accel::Ray> r, std::span<accel::Hit> h) {
        accel::trace_parallel(brute, r, h, accel::Query::closest, TracePath::scalar);
    };
#if defined(ARBOR_SANITIZED_BUILD)
    constexpr std::size_t count = 512;
#else
    constexpr std::size_t count = 4096;
#endif
    std::vector<std::unique_ptr<accel::Accel>> structures;
    for (const auto kind : {accel::AccelKind::bvh_median, accel::AccelKind::bvh_sah, accel::AccelKind::lbvh, accel::AccelKind::kdtree})
        structures.push_back(accel::make_accel(kind, view));
    for (const auto kind : {engine::RayKind::shadow, engine::RayKind::diffuse}) {
        CAPTURE(engine::to_string(kind));
        engine::RayGenConfig rc;
        rc.kind = kind;
        rc.count = count;
        rc.seed = 1;
        const std::vector<accel::Ray> rays = engine::generate_rays(gs, rc, tracer);
        REQUIRE(rays.size() == count);
        const auto q = kind == engine::RayKind::shadow ? accel::Query::any : accel::Query::closest;
        std::vector<accel::Hit> ref(rays.size());
        accel::trace_parallel(brute, rays, ref, q, TracePath::scalar);
        // A ray that starts above the floor plane (y = 0) and goes up cannot hit a triangle in that
        // plane: such a hit is a re-hit of the floor it was spawned from.
        std::size_t rehits = 0, floor_spawned = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            if (!(rays[i].org.y > 0.0f && rays[i].org.y < 1e-2f && rays[i].dir.y > 0.0f)) continue;
            ++floor_spawned;
            if (!ref[i].is_hit()) continue;
            bool in_floor = true;
            for (int k = 0; k < 3; ++k) in_floor = in_floor && view.corner(ref[i].prim, k).y == 0.0f;
            rehits += in_floor;
        }
        CHECK(floor_spawned > count / 4);
        CHECK(rehits == 0);
        for (const auto& a : structures)
            for (const TracePath p : {TracePath::scalar, TracePath::packet, TracePath::single}) {
                CAPTURE(accel::to_string(a->kind()));
                CAPTURE(accel::to_string(p));
                std::vector<accel::Hit> got(rays.size());
                accel::trace_parallel(*a, rays, got, q, p);
                std::size_t bad = 0;
                for (std::size_t i = 0; i < rays.size(); ++i)
                    bad += q == accel::Query::any ? got[i].is_hit() != ref[i].is_hit() : !accel::hits_agree(got[i], ref[i]);
                CHECK(bad == 0);
            }
    }
}
