// The single-ray walk from a root test done beforehand for a group of rays (accel/wide/wide_root.h:
// test_root, then traverse_wide_root) against the walk that tests the root itself (traverse_wide
// from (0, 0)): for every ray the same leaves in the same order, and bit-identical hits (closest
// and any), at every width of the build, over the procedural scene and the bunny, with both box
// forms (WideRay::plain and not: the rays with tnear < 0). The rays: the
// three kinds of testing.h, the same rays again with [tnear, tfar] moved behind the origin
// (negative distances: the box test's slack for negative exits) or around it, and groups cut short
// by the end of the batch.
#include "accel/bvh/bvh_accel.h"
#include "accel/wide/wide_paths_impl.h"
#include "engine/obj_loader.h"
#include "testing.h"

#include <doctest/doctest.h>

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
    rays.resize(rays.size() - 5);  // the last group partial
    return rays;
}

struct Counts {
    std::size_t rays = 0, lone = 0, several = 0, leaves = 0, hits = 0, general = 0;
};

template <std::size_t N> void check_width(const accel::TriangleView& view, const std::vector<Ray>& rays, Counts& c) {
    if constexpr (accel::wide_width_available<N>()) {
        using T = accel::WideLane<N>;
        using Setup = simd::WideRaySetup<simd::SetupLane>;
        accel::BuildConfig cfg;
        cfg.layouts = accel::Layouts::simd;
        cfg.wide.width = N;
        const auto acc = accel::make_accel(accel::AccelKind::bvh_sah, view, cfg);
        const auto* w = dynamic_cast<const accel::WideBvhAccel<N>*>(acc.get());
        REQUIRE(w != nullptr);
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
                    continue;
                }
                ++c.rays;
                const std::uint32_t visits = root.live[i] + std::popcount(root.rest[i]);
                c.lone += visits == 1;
                c.several += visits > 1;
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
                                                               root.rest[i], root.entry(i), rec(b));
                } else {
                    accel::traverse_wide<false, false>(layout, r, tfar, stack, 0, 0, rec(a));
                    if (root.live[i])
                        accel::traverse_wide_root<false, false>(layout, r, tfar, stack, root.child[i], root.count[i],
                                                                root.rest[i], root.entry(i), rec(b));
                }
                order_differs += a != b;
                c.leaves += a.size();
                c.general += !r.plain;
                for (const bool any : {false, true}) {
                    simd::WideRay<T> q1 = r, q2 = r;
                    const Hit h = any ? w->template trace_from<true>(q1, in[i].tfar, 0, 0, stack)
                                      : w->template trace_from<false>(q1, in[i].tfar, 0, 0, stack);
                    const Hit g = any ? w->template trace_root<true>(q2, in[i].tfar, root, i, stack)
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
                    << c.several << ", leaves visited " << c.leaves << ", hits " << c.hits);
    // Both kinds of root outcome, leaves and hits occur (so the comparisons above compare walks).
    CHECK(c.lone > c.rays / 50);
    CHECK(c.several > c.rays / 10);
    CHECK(c.leaves > c.rays);
    CHECK(c.hits > c.rays / 4);
    CHECK(c.general > c.rays / 10);
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
