// The single-ray walk from a root test done beforehand for a group of rays (accel/wide/wide_root.h:
// test_root, then traverse_wide_root) against the walk that tests the root itself (traverse_wide
// from (0, 0)): for every ray the same leaves in the same order, and bit-identical hits (closest
// and any), at every width of the build, over the procedural scene and the bunny, with both box
// forms (WideRay::plain and not: the rays with tnear < 0). The rays: the
// three kinds of testing.h, the same rays again with [tnear, tfar] moved behind the origin
// (negative distances: the box test's slack for negative exits) or around it, rays no path traces,
// and groups cut short by the end of the batch; then a stiff case: a root child entered past a
// negative tfar, within the slack (visited: slab_accept's rule).
#include "accel/structures/bvh_accel.h"
#include "accel/structures/wide_paths_impl.h"
#include "engine/obj_loader.h"
#include "testing.h"
#include "wide_bvh.h"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <utility>
#include <vector>

using namespace arbor;
using accel::Hit;
using accel::Ray;

namespace {

/// The rays, then the same rays over [-2L, -L / 8] and [-L, L] (L: the bounds' diagonal).
std::vector<Ray> with_ranges(const accel::Bounds& b, std::vector<Ray> rays) {
    const accel::Vec3f e = b.extent();
    const float len = std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z);
    const std::size_t n = rays.size();
    for (std::size_t i = 0; i < n; ++i) {
        Ray r = rays[i];
        r.tnear = -2.0f * len, r.tfar = -len / 8.0f;
        rays.push_back(r);
        r.tnear = -len, r.tfar = len;
        rays.push_back(r);
    }
    // Rays no path traces (simd/ray.h, traceable): a NaN origin, a zero direction, tnear > tfar.
    for (std::size_t i = 0; i < 40; i += 4) {
        Ray r = rays[i];
        r.org.x = NAN;
        rays.push_back(r);
        r = rays[i + 1];
        r.dir = {0.0f, 0.0f, 0.0f};
        rays.push_back(r);
        r = rays[i + 2];
        std::swap(r.tnear, r.tfar);
        r.tnear = r.tfar + 1.0f;
        rays.push_back(r);
    }
    rays.resize(rays.size() - 5);  // the last group partial
    return rays;
}

struct Counts {
    std::size_t rays = 0, lone = 0, several = 0, deeper = 0, leaves = 0, hits = 0, general = 0, untraceable = 0;
};

template <std::size_t N> void check_width(const accel::TriangleView& view, const std::vector<Ray>& rays, Counts& c) {
    if constexpr (accel::wide_width_available<N>()) {
        using T = accel::WideLane<N>;
        using Setup = simd::WideRaySetup<simd::SetupLane>;
        const auto acc = testing::wide_bvh<N>(view);
        const auto* w = dynamic_cast<const accel::WideBvhAccel<N>*>(acc.get());
        const accel::WideLayout<N>& layout = w->wide_layout();
        REQUIRE(!layout.empty());
        accel::WideStack stack(layout.stack_size());
        Setup setup;
        accel::RootTests<N, Setup::size> root;
        std::size_t order_differs = 0, hit_differs = 0;
        for (std::size_t base = 0; base < rays.size(); base += Setup::size) {
            const auto in = std::span<const Ray>(rays).subspan(base, std::min(Setup::size, rays.size() - base));
            simd::wide_ray_setup(in, setup);
            accel::test_root(layout, setup, in.size(), root);
            for (std::size_t i = 0; i < in.size(); ++i) {
                simd::WideRay<T> r;
                setup.get(i, r);
                if (!r.traceable) {
                    CHECK(!root.live[i]);
                    ++c.untraceable;
                    continue;
                }
                ++c.rays;
                const std::uint32_t visits = root.live[i] + std::popcount(root.rest[i]);
                c.lone += visits == 1;
                c.several += visits > 1;
                c.deeper += root.live[i] && root.count[i] == 0;  // first child a node: its test from the pass
                // The leaves visited, in order, by a walk that finds no hit (so it visits every
                // leaf it can reach), from (0, 0) and from the stored root test.
                std::vector<std::pair<std::uint32_t, std::uint32_t>> a, b;
                const float tfar = in[i].tfar;
                auto rec = [](auto& seen) {
                    return [&seen](std::uint32_t first, std::uint32_t count) {
                        seen.emplace_back(first, count);
                        return false;
                    };
                };
                if (r.plain) {
                    accel::traverse_wide<false, true>(layout, r, tfar, stack, 0, 0, rec(a));
                    if (root.live[i])
                        accel::traverse_wide_root<false, true>(layout, r, tfar, stack, root.child[i], root.count[i],
                                                               root.rest[i], root.entry(i), root.bits2[i], root.t2[i], rec(b));
                } else {
                    accel::traverse_wide<false, false>(layout, r, tfar, stack, 0, 0, rec(a));
                    if (root.live[i])
                        accel::traverse_wide_root<false, false>(layout, r, tfar, stack, root.child[i], root.count[i],
                                                                root.rest[i], root.entry(i), root.bits2[i], root.t2[i], rec(b));
                }
                order_differs += a != b;
                c.leaves += a.size();
                c.general += !r.plain;
                for (const bool any : {false, true}) {
                    simd::WideRay<T> q1 = r, q2 = r;
                    const Hit h = any ? w->template trace_from<true>(q1, in[i].tfar, 0, 0, stack)
                                      : w->template trace_from<false>(q1, in[i].tfar, 0, 0, stack);
                    // (trace_root walks only rays with a root child to visit, as trace_group does; the
                    // others' walk from the root must find no hit.)
                    const Hit g = !root.live[i] ? Hit{}
                                  : any         ? w->template trace_root<true>(q2, in[i].tfar, root, i, stack)
                                                : w->template trace_root<false>(q2, in[i].tfar, root, i, stack);
                    hit_differs += std::memcmp(&h, &g, sizeof(Hit)) != 0;
                    c.hits += g.is_hit();
                }
            }
        }
        CAPTURE(N);
        CHECK(order_differs == 0);
        CHECK(hit_differs == 0);
    }
}

void check_all_widths(const accel::TriangleView& view, const std::vector<Ray>& rays) {
    Counts c;
    check_width<4>(view, rays, c);
    check_width<8>(view, rays, c);
    check_width<16>(view, rays, c);
    MESSAGE("rays " << c.rays << " (" << c.general << " not plain), one root child to visit " << c.lone << ", several "
                    << c.several << ", first child a node " << c.deeper << ", leaves visited " << c.leaves << ", hits " << c.hits);
    // Both kinds of root outcome, leaves and hits occur (so the comparisons above compare walks).
    CHECK(c.lone > c.rays / 50);
    CHECK(c.several > c.rays / 10);
    CHECK(c.deeper > c.rays / 10);
    CHECK(c.leaves > c.rays);
    CHECK(c.hits > c.rays / 4);
    CHECK(c.general > c.rays / 10);
    CHECK(c.untraceable >= 25);
}

}  // namespace

TEST_CASE("wide root: the walk from a group's root tests visits the leaves of the plain walk in its order, same hits") {
    const engine::Mesh mesh = testing::procedural_shapes();
    check_all_widths(mesh.view(), with_ranges(mesh.bounds, testing::three_kinds(mesh.bounds, 1500, 11)));

    for (const auto& path : testing::model_paths()) {
        if (std::filesystem::path(path).stem() != "stanford-bunny") continue;
        engine::Warnings warn;
        const engine::Mesh bunny = engine::load_obj(path, warn);
        check_all_widths(bunny.view(), with_ranges(bunny.bounds, testing::three_kinds(bunny.bounds, 1500, 13)));
    }
}

namespace {

/// The stiff case below at width N: whether the walk from the stored root test visits the leaves
/// of the walk from (0, 0), and that those are C's only, with A's children hit by the root test.
template <std::size_t N> void check_past_tfar(const engine::Mesh& mesh, const Ray& ray, std::size_t& checked) {
    if constexpr (accel::wide_width_available<N>()) {
        using T = accel::WideLane<N>;
        using Setup = simd::WideRaySetup<simd::SetupLane>;
        const auto acc = testing::wide_bvh<N>(mesh.view());
        const auto* w = dynamic_cast<const accel::WideBvhAccel<N>*>(acc.get());
        const accel::WideLayout<N>& layout = w->wide_layout();
        accel::WideStack stack(layout.stack_size());
        Setup setup;
        accel::RootTests<N, Setup::size> root;
        const std::vector<Ray> rays(3, ray);  // (a partial group)
        simd::wide_ray_setup(std::span<const Ray>(rays), setup);
        accel::test_root(layout, setup, rays.size(), root);
        simd::WideRay<T> r;
        setup.get(0, r);
        REQUIRE(r.traceable);
        REQUIRE(!r.plain);
        // The root's own test: children of both groups hit, some entered past tfar.
        T t;
        const std::uint32_t bits = simd::to_bits(simd::ray_boxes<T>(r, &layout.nodes[0].boxes.b[0][0][0], t));
        std::uint32_t past = 0;
        for (std::uint32_t m = bits; m != 0; m &= m - 1) past += simd::lane(t, std::size_t(std::countr_zero(m))) > ray.tfar;
        CAPTURE(N);
        REQUIRE(std::popcount(bits) >= 2);
        REQUIRE(past >= 1);
        std::vector<std::pair<std::uint32_t, std::uint32_t>> a, b;
        auto rec = [](auto& seen) {
            return [&seen](std::uint32_t first, std::uint32_t count) {
                seen.emplace_back(first, count);
                return false;
            };
        };
        accel::traverse_wide<false, false>(layout, r, ray.tfar, stack, 0, 0, rec(a));
        REQUIRE(root.live[0]);
        accel::traverse_wide_root<false, false>(layout, r, ray.tfar, stack, root.child[0], root.count[0], root.rest[0],
                                                root.entry(0), root.bits2[0], root.t2[0], rec(b));
        CHECK(a == b);
        REQUIRE(!a.empty());
        std::size_t of_a = 0;
        for (const auto& [first, count] : a)
            for (std::uint32_t s = 0; s < count; ++s) of_a += layout.prim(std::size_t(first) * N + s) < 20;
        CHECK(of_a > 0);
        ++checked;
    }
}

}  // namespace

TEST_CASE("wide root: a root child entered just past a negative tfar (within the box test's slack) is visited, by the walk and the root tests alike") {
    // A ray along +x from the origin over [tnear, tfar] = [-10, -5]. Group C (triangles 20-39, x in
    // [-7, -6]) is entered at -7 <= tfar. Group A (triangles 0-19, x from 1 ulp above -5 to -1) is
    // entered at -4.9999995 > tfar, and the box test accepts it all the same (a negative exit, here
    // tfar, gets 2^-17 of room: slab_accept). A's boxes reach down to y = -100, so the root's order
    // for the ray's octant puts them nearer than C's: the walk pops an A child first and, by the
    // same rule as the box test (slab_accept; a plain `entry <= tfar` here culled boxes the box test
    // had accepted, and lost hits behind the origin: test_behind_origin.cpp), visits it. The root
    // tests must pick their first child by that rule too: a == b, and A's leaves are visited.
    engine::Mesh mesh;
    const auto add = [&mesh](accel::Vec3f p, accel::Vec3f q, accel::Vec3f s) {
        for (const accel::Vec3f& v : {p, q, s}) {
            mesh.indices.push_back(std::uint32_t(mesh.x.size()));
            mesh.x.push_back(v.x), mesh.y.push_back(v.y), mesh.z.push_back(v.z);
        }
    };
    const float xa = std::nextafter(-5.0f, 0.0f);
    for (int i = 0; i < 20; ++i) add({xa, -100.0f, 0.0f}, {-1.0f, 1.0f, -0.5f - 0.01f * float(i)}, {-1.0f, 1.0f, 0.5f + 0.01f * float(i)});
    for (int i = 0; i < 20; ++i)
        add({-7.0f, -1.0f, -1.0f - 0.01f * float(i)}, {-6.0f, 1.0f, 0.0f}, {-6.5f, 1.0f, 1.0f + 0.01f * float(i)});
    mesh.compute_bounds();
    Ray ray;
    ray.org = {0.0f, 0.0f, 0.0f};
    ray.dir = {1.0f, 0.0f, 0.0f};
    ray.tnear = -10.0f;
    ray.tfar = -5.0f;
    std::size_t checked = 0;
    check_past_tfar<4>(mesh, ray, checked);
    check_past_tfar<8>(mesh, ray, checked);
    check_past_tfar<16>(mesh, ray, checked);
    CHECK(checked >= 1);
}
