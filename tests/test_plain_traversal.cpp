// The single-ray path's two box forms (simd::ray_boxes and, for rays with WideRay::plain set,
// simd::ray_boxes_plain) walk the same tree to bit-identical answers: every ray traced with the
// form it gets and again with the general form forced, at every width of the build, over a
// procedural scene and the bunny. (The kernels themselves are compared lane by lane in
// test_simd_kernels.cpp; both forms against brute in test_wide_paths.cpp, whose rays are plain.)
#include "accel/structures/bvh_accel.h"
#include "accel/structures/wide_paths_impl.h"
#include "engine/obj_loader.h"
#include "testing.h"
#include "wide_bvh.h"

#include <doctest/doctest.h>

#include <cstring>
#include <filesystem>

using namespace arbor;
using accel::Hit;
using accel::Ray;

namespace {

template <std::size_t N> void check_forms(const accel::TriangleView& view, const std::vector<Ray>& rays) {
    if constexpr (accel::wide_width_available<N>()) {
        const auto acc = testing::wide_bvh<N>(view);
        const auto* w = dynamic_cast<const accel::WideBvhAccel<N>*>(acc.get());
        accel::WideStack stack(w->wide_layout().stack_size());
        std::size_t plain = 0, hits = 0, differ = 0;
        for (const Ray& ray : rays) {
            for (const bool any : {false, true}) {
                auto r = simd::wide_ray<accel::WideLane<N>>(ray.org, ray.dir, ray.tnear, ray.tfar);
                if (!r.traceable) continue;
                plain += r.plain && !any;
                const auto trace = [&](auto r2) {
                    return any ? w->template trace_from<true>(r2, ray.tfar, 0, 0, stack)
                               : w->template trace_from<false>(r2, ray.tfar, 0, 0, stack);
                };
                const Hit h = trace(r);
                r.plain = false;
                const Hit g = trace(r);
                hits += h.is_hit();
                differ += std::memcmp(&h, &g, sizeof(Hit)) != 0;
            }
        }
        CAPTURE(N);
        CHECK(differ == 0);
        CHECK(plain > rays.size() / 2);
        CHECK(hits > rays.size() / 4);
    }
}

void check_all_widths(const accel::TriangleView& view, const std::vector<Ray>& rays) {
    check_forms<4>(view, rays);
    check_forms<8>(view, rays);
    check_forms<16>(view, rays);
}

}  // namespace

TEST_CASE("plain box form: bit-identical answers to the general form on procedural scenes and the bunny") {
    const engine::Mesh mesh = testing::procedural_shapes();
    check_all_widths(mesh.view(), testing::three_kinds(mesh.bounds, 2000, 3));

    for (const auto& path : testing::model_paths()) {
        if (std::filesystem::path(path).stem() != "stanford-bunny") continue;
        engine::Warnings warn;
        const engine::Mesh bunny = engine::load_obj(path, warn);
        check_all_widths(bunny.view(), testing::three_kinds(bunny.bounds, 3000, 5));
    }
}
