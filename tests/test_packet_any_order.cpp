// The packet walk's any-hit child order (accel/wide/wide_packet.h): a node's hit children are
// visited farthest first (closest hit: nearest first). Sixteen walls across the x axis, every
// ray of a packet crossing all of them: the first leaf an any-hit packet tests is then one of the
// walls farthest along the rays, and each lane reports a wall of the far half (nearest first, as
// before, reported the first wall). Both packet branches: lanes in one direction octant (the
// node's octant order) and in two (the entry-distance order); rays along +x and along -x; every
// width and packet size of the build, bvh-sah and lbvh. Every answer is also checked as any hit:
// the named triangle lies on the wall at the reported t.
#include "accel/factory/make_accel.h"
#include "accel/interface/accel.h"
#include "engine/mesh.h"

#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

using namespace arbor;
using accel::Hit;
using accel::Ray;
using accel::Vec3f;

namespace {

constexpr int kWalls = 16;
constexpr int kTrisPerWall = 8;  // a 2 x 2 grid of quads
constexpr float kSpacing = 10.0f;

/// Wall w at x = kSpacing * w, spanning y, z in [-2, 2]; its triangles are prims
/// w * kTrisPerWall .. (w + 1) * kTrisPerWall - 1.
engine::Mesh walls() {
    engine::Mesh m;
    for (int w = 0; w < kWalls; ++w) {
        const float x = kSpacing * float(w);
        for (int a = 0; a < 2; ++a)
            for (int b = 0; b < 2; ++b) {
                const float y0 = -2.0f + 2.0f * float(a), z0 = -2.0f + 2.0f * float(b);
                const auto p0 = m.add_vertex({x, y0, z0}), p1 = m.add_vertex({x, y0 + 2.0f, z0});
                const auto p2 = m.add_vertex({x, y0 + 2.0f, z0 + 2.0f}), p3 = m.add_vertex({x, y0, z0 + 2.0f});
                m.add_triangle(p0, p1, p2);
                m.add_triangle(p0, p2, p3);
            }
    }
    m.compute_bounds();
    return m;
}

/// 64 rays (packets of 4, 8 or 16 consecutive rays) from x0 along sign * x, origins spread in
/// y, z over [-0.5, 0.5]; mixed: the y component of the direction alternates in sign from ray to
/// ray (two octants in every packet).
std::vector<Ray> rays_along_x(float x0, float sign, bool mixed) {
    std::vector<Ray> rays;
    for (int i = 0; i < 64; ++i) {
        Ray r;
        r.org = {x0, -0.5f + float(i % 8) / 7.0f, -0.5f + float(i / 8) / 7.0f};
        const float dy = mixed ? (i % 2 ? -0.001f : 0.001f) : 0.001f;
        r.dir = {sign, dy, 0.002f};
        r.tnear = 0.0f;
        r.tfar = 1000.0f;
        rays.push_back(r);
    }
    return rays;
}

}  // namespace

TEST_CASE("packet any hit: a node's hit children are visited farthest first") {
    const engine::Mesh mesh = walls();
    const float last = kSpacing * float(kWalls - 1);
    for (const auto kind : {accel::AccelKind::bvh_sah, accel::AccelKind::lbvh})
        for (const std::uint32_t width : {4u, 8u, 16u})
            for (const std::uint32_t lanes : {0u, 8u}) {
                accel::BuildConfig cfg;
                cfg.wide.width = width;
                cfg.packets.lanes = lanes;
                const auto acc = accel::make_accel(kind, mesh.view(), cfg);
                for (const float sign : {1.0f, -1.0f})
                    for (const bool mixed : {false, true}) {
                        const float x0 = sign > 0 ? -5.0f : last + 5.0f;
                        const std::vector<Ray> rays = rays_along_x(x0, sign, mixed);
                        std::vector<Hit> any(rays.size()), closest(rays.size());
                        acc->trace(rays, any, {accel::Query::any, accel::TracePath::packet});
                        acc->trace(rays, closest, {accel::Query::closest, accel::TracePath::packet});
                        CAPTURE(accel::to_string(kind));
                        CAPTURE(width);
                        CAPTURE(lanes);
                        CAPTURE(sign);
                        CAPTURE(mixed);
                        int near_half = 0, off_wall = 0, missed = 0, closest_wrong = 0;
                        for (std::size_t i = 0; i < rays.size(); ++i) {
                            const int first = sign > 0 ? 0 : kWalls - 1;
                            closest_wrong += !closest[i].is_hit() || int(closest[i].prim) / kTrisPerWall != first;
                            if (!any[i].is_hit()) {
                                ++missed;
                                continue;
                            }
                            const int w = int(any[i].prim) / kTrisPerWall;
                            // Walls passed before wall w, counted from the rays' origin.
                            const int crossed = sign > 0 ? w : kWalls - 1 - w;
                            near_half += crossed < kWalls / 2;
                            const float x = rays[i].org.x + any[i].t * rays[i].dir.x;
                            off_wall += std::fabs(x - kSpacing * float(w)) > 1e-3f;
                        }
                        CHECK(closest_wrong == 0);
                        CHECK(missed == 0);
                        CHECK(off_wall == 0);
                        CHECK(near_half == 0);
                    }
            }
}
