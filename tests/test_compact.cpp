// Compact mode (BuildConfig::compact, accel/wide/compact_layout.h): its quantized boxes always
// contain the true ones (random and stiff boxes: tiny, huge, far from the origin, degenerate;
// decoded in float and in SIMD lanes alike), and its closest hits equal brute force's bit for
// bit (t, prim, u, v), its any hits brute's hit or miss, on every shared model,
// procedural shapes, edge- and vertex-aimed rays and a mesh moved 1e5 away; at half the bytes.
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <random>

#include "accel/bvh/bvh_build.h"
#include "accel/bvh/build_prims.h"
#include "accel/factory/make_accel.h"
#include "accel/structures/brute_accel.h"
#include "accel/wide/compact_quantize.h"
#include "accel/wide/compact_traverse.h"
#include "engine/obj_loader.h"
#include "testing.h"

using namespace arbor;
using accel::Hit;
using accel::Ray;
using accel::Vec3f;

namespace {

bool same_bits(const Hit& a, const Hit& b) { return std::memcmp(&a, &b, sizeof(Hit)) == 0; }

/// Every child box of a random node is contained in its decoded box, and each plane is the
/// tightest step that is (one step in would cut the box).
void check_frame(const std::vector<std::pair<float, float>>& boxes) {
    float lo = INFINITY, hi = -INFINITY;
    for (const auto& [l, h] : boxes) lo = std::min(lo, l), hi = std::max(hi, h);
    const accel::CompactAxis a = accel::CompactAxis::fit(lo, hi);
    CHECK(a.decode(255) >= hi);
    for (const auto& box : boxes) {
        // (Named copies, not structured bindings: clang 14's CAPTURE cannot take those.)
        const float l = box.first, h = box.second;
        CAPTURE(l);
        CAPTURE(h);
        const std::uint8_t ql = a.quantize_lo(l), qh = a.quantize_hi(h);
        REQUIRE(a.decode(ql) <= l);
        REQUIRE(a.decode(qh) >= h);
        if (ql < 255) CHECK(a.decode(std::uint8_t(ql + 1)) > l);
        if (qh > 0) CHECK(a.decode(std::uint8_t(qh - 1)) < h);
        CHECK(a.decode(ql) <= a.decode(qh));
    }
}

std::vector<Hit> trace(const accel::Accel& a, const std::vector<Ray>& rays, accel::Query q,
                       accel::TracePath path = accel::TracePath::best) {
    std::vector<Hit> hits(rays.size());
    a.trace(rays, hits, {q, path});
    return hits;
}

/// Rays at the mesh's edges' midpoints and vertices from random origins around it (the
/// watertight test's ties), random rays through its box, and for the packet path coherent ones:
/// a camera grid and rays from the centres of consecutive triangles towards one light.
std::vector<Ray> stiff_rays(const engine::Mesh& mesh, std::size_t n, std::uint32_t seed) {
    const auto v = mesh.view();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const Vec3f c = mesh.bounds.center(), e = mesh.bounds.extent();
    std::vector<Ray> rays = testing::random_rays_into(mesh.bounds, n, seed);
    for (std::size_t i = 0; i < n && v.triangle_count() != 0; ++i) {
        const std::size_t t = rng() % v.triangle_count();
        const int k = int(rng() % 3);
        const Vec3f a = v.corner(t, k), b = v.corner(t, (k + 1) % 3);
        const Vec3f target = (i % 2) ? a : (a + b) * 0.5f;
        const Vec3f o = c + Vec3f{u(rng) * e.x, u(rng) * e.y, u(rng) * e.z} * 1.5f;
        rays.push_back({o, 0.0f, target - o, INFINITY});
    }
    const auto camera = testing::camera_rays(mesh.bounds, 40, 40);
    rays.insert(rays.end(), camera.begin(), camera.end());
    const Vec3f light = c + Vec3f{0.2f, 1.0f, 0.3f} * (2.0f * simd::length(e));
    const std::size_t start = v.triangle_count() != 0 ? rng() % v.triangle_count() : 0;
    for (std::size_t i = 0; i < n && v.triangle_count() != 0; ++i) {
        const std::size_t t = (start + i) % v.triangle_count();
        const Vec3f p = (v.corner(t, 0) + v.corner(t, 1) + v.corner(t, 2)) * (1.0f / 3.0f);
        rays.push_back({p, 1e-4f, light - p, 1.0f});
    }
    return rays;
}

/// Compact builds (every width, bvh-sah and lbvh) against brute force, the oracle: closest hits
/// bit for bit on the `single` and the `packet` path (and `best`, their choice), vertex-aimed rays
/// included (ray_box.h, box_tfar); any hits by hit or miss. Returns how many closest hits of the
/// bvh-sah scalar path differ from brute's (none may: checked by the callers).
std::size_t check_compact(const engine::Mesh& mesh, const std::vector<Ray>& rays) {
    const accel::BruteAccel brute(mesh.view());
    const auto closest = trace(brute, rays, accel::Query::closest);
    for (const std::uint32_t width : {4u, 8u, 16u}) {
        accel::BuildConfig cfg;
        cfg.compact = true;
        cfg.wide.width = width;
        CAPTURE(width);
        for (const auto kind : {accel::AccelKind::bvh_sah, accel::AccelKind::lbvh}) {
            CAPTURE(accel::to_string(kind));
            const auto compact = accel::make_accel(kind, mesh.view(), cfg);
            CHECK(compact->offer().runs(accel::TracePath::single, accel::Query::closest));
            CHECK(compact->offer().runs(accel::TracePath::packet, accel::Query::closest));
            for (const auto path : {accel::TracePath::best, accel::TracePath::single, accel::TracePath::packet}) {
                CAPTURE(accel::to_string(path));
                const auto got = trace(*compact, rays, accel::Query::closest, path);
                std::size_t bad = 0;
                for (std::size_t i = 0; i < rays.size(); ++i) {
                    if (same_bits(got[i], closest[i])) continue;
                    if (++bad <= 3) {
                        CAPTURE(i);
                        CAPTURE(got[i].prim);
                        CAPTURE(closest[i].prim);
                        CAPTURE(std::bit_cast<std::uint32_t>(got[i].t));
                        CAPTURE(std::bit_cast<std::uint32_t>(closest[i].t));
                        CHECK(same_bits(got[i], closest[i]));
                    }
                }
                CHECK(bad == 0);
            }
            for (const auto path : {accel::TracePath::best, accel::TracePath::single, accel::TracePath::packet}) {
                CAPTURE(accel::to_string(path));
                const auto any = trace(*compact, rays, accel::Query::any, path);
                CHECK(testing::count_occlusion_disagreements(any, closest) == 0);
            }
        }
    }
    accel::BuildConfig scalar_cfg;
    scalar_cfg.layouts = accel::Layouts::scalar;
    const auto scalar = accel::make_accel(accel::AccelKind::bvh_sah, mesh.view(), scalar_cfg);
    const auto ref = trace(*scalar, rays, accel::Query::closest, accel::TracePath::scalar);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) differ += !same_bits(ref[i], closest[i]);
    return differ;
}

}  // namespace

TEST_CASE("compact: quantized planes contain the true ones (random, tiny, huge, offset, degenerate boxes)") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (const float offset : {0.0f, 1e5f, -1e5f, 3e7f, 1e-30f})
        for (const float size : {1e-30f, 1e-6f, 1.0f, 1e3f, 1e20f, 1e37f})
            for (int rep = 0; rep < 20; ++rep) {
                std::vector<std::pair<float, float>> boxes;
                const int n = 1 + int(rng() % 16);
                for (int c = 0; c < n; ++c) {
                    float a = offset + size * u(rng), b = offset + size * u(rng);
                    if (rep % 5 == 0) b = a;  // degenerate (flat) boxes
                    boxes.emplace_back(std::min(a, b), std::max(a, b));
                }
                check_frame(boxes);
            }
    // Extremes: the whole float range, one point, neighbours one ulp apart.
    check_frame({{-3.4e38f, 3.4e38f}, {0.0f, 1.0f}});
    check_frame({{1e5f, 1e5f}});
    check_frame({{1.0f, std::nextafter(1.0f, 2.0f)}, {std::nextafter(1.0f, 2.0f), std::nextafter(1.0f, 2.0f)}});
    check_frame({{-0.0f, 0.0f}});
    check_frame({{-1e-38f, 1e-38f}, {-3e-39f, 2e-45f}});
}

TEST_CASE("compact: a node's planes decoded in SIMD lanes are the scalar decode, bit for bit") {
    using T = accel::WideLane<4>;
    std::mt19937 rng(5);
    accel::CompactNode<4> n{};
    n.children = 4;
    for (int rep = 0; rep < 200; ++rep) {
        for (int k = 0; k < 3; ++k) {
            n.origin[k] = std::ldexp(float(int(rng() % 2001) - 1000), int(rng() % 80) - 40);
            n.scale[k] = std::ldexp(1.0f, int(rng() % 250) - 125);
            for (int s = 0; s < 2; ++s)
                for (int c = 0; c < 4; ++c) n.q[s][k][c] = std::uint8_t(rng());
        }
        const simd::BoxesSoA<4> ref = accel::decode_boxes(n);
        for (int s = 0; s < 2; ++s)
            for (int k = 0; k < 3; ++k) {
                alignas(16) float got[4];
                simd::store_lanes(accel::compact_decode(accel::load_steps<T>(n.q[s][k]), T(n.scale[k]), T(n.origin[k])),
                                  got);
                CHECK(std::memcmp(got, ref.b[s][k], sizeof got) == 0);
            }
    }
}

TEST_CASE("compact: every shared model, closest hits bit for bit with brute force, any hits agree") {
    for (const auto& path : testing::model_paths()) {
        CAPTURE(path);
        engine::Warnings w;
        const engine::Mesh mesh = engine::load_obj(path, w);
#if defined(ARBOR_SANITIZED_BUILD)
        const std::size_t rays = mesh.triangle_count() > 30000 ? 150 : 400;  // (brute's cost: rays x triangles)
#else
        const std::size_t rays = mesh.triangle_count() > 30000 ? 600 : 1500;
#endif
        CHECK(check_compact(mesh, stiff_rays(mesh, rays, 3)) == 0);
    }
}

TEST_CASE("compact: procedural shapes, edge and vertex rays, and the same mesh 1e5 away") {
    engine::Mesh mesh = testing::procedural_shapes();
    CHECK(check_compact(mesh, stiff_rays(mesh, 2000, 7)) == 0);
    testing::place(mesh, 1e5f, 1.0f);
    CHECK(check_compact(mesh, stiff_rays(mesh, 2000, 8)) == 0);
}

TEST_CASE("compact: about half the bytes of the default layout, and what it leaves out") {
    const engine::Mesh mesh = testing::procedural_shapes();
    accel::BuildConfig simd_cfg;
    simd_cfg.layouts = accel::Layouts::simd;
    accel::BuildConfig compact_cfg = simd_cfg;
    compact_cfg.compact = true;
    const auto wide = accel::make_accel(accel::AccelKind::bvh_sah, mesh.view(), simd_cfg);
    const auto compact = accel::make_accel(accel::AccelKind::bvh_sah, mesh.view(), compact_cfg);
    CAPTURE(wide->stats().bytes_per_triangle());
    CAPTURE(compact->stats().bytes_per_triangle());
    CHECK(compact->stats().memory_bytes * 2 <= wide->stats().memory_bytes + wide->stats().memory_bytes / 10);
    CHECK(!compact->offer().counts);
    CHECK(!compact->refit_unsupported().empty());
    const accel::PathOffer expected = accel::expected_offer(accel::AccelKind::bvh_sah, compact_cfg);
    CHECK(std::memcmp(expected.queries, compact->offer().queries, sizeof expected.queries) == 0);
    CHECK(expected.packets_pay == compact->offer().packets_pay);
}

namespace {
/// make_compact_layout from a full wide layout and from an ids-only one (WideLeaves::ids) of
/// the same tree: the same nodes, blocks and orders, byte for byte.
template <std::size_t N> void check_ids_only_source(const engine::Mesh& mesh) {
    CAPTURE(N);
    accel::BvhBuildConfig bcfg;
    bcfg.leaf_floor = std::uint32_t(N);
    const accel::BinaryBvh bvh = accel::build_bvh_sah(accel::make_build_prims(mesh.view()), bcfg);
    accel::WideLayout<N> full = accel::make_wide_layout<N>(bvh, mesh.view(), {}, accel::WideLeaves::blocks);
    accel::WideLayout<N> ids = accel::make_wide_layout<N>(bvh, mesh.view(), {}, accel::WideLeaves::ids);
    CHECK(ids.blocks.empty());
    REQUIRE(ids.block_count() == full.block_count());
    for (std::size_t slot = 0; slot < full.block_count() * N; ++slot) REQUIRE(ids.prim(slot) == full.prim(slot));
    CHECK(ids.memory_bytes() * 2 < full.memory_bytes());
    const accel::CompactLayout<N> a = accel::make_compact_layout<N>(std::move(full), mesh.view());
    const accel::CompactLayout<N> b = accel::make_compact_layout<N>(std::move(ids), mesh.view());
    REQUIRE(a.nodes.size() == b.nodes.size());
    REQUIRE(a.refs.size() == b.refs.size());
    REQUIRE(a.orders.size() == b.orders.size());
    // (Field by field: the padding and the slots past `children` are never written.)
    std::size_t differ = 0;
    for (std::size_t i = 0; i < a.nodes.size(); ++i) {
        const accel::CompactNode<N>&x = a.nodes[i], &y = b.nodes[i];
        bool same = x.children == y.children && std::memcmp(x.origin, y.origin, sizeof x.origin) == 0 &&
                    std::memcmp(x.scale, y.scale, sizeof x.scale) == 0;
        for (std::size_t c = 0; same && c < x.children; ++c) {
            same = x.child[c] == y.child[c] && x.count[c] == y.count[c];
            for (int side = 0; side < 2; ++side)
                for (int k = 0; k < 3; ++k) same = same && x.q[side][k][c] == y.q[side][k][c];
        }
        differ += same ? 0 : 1;
    }
    CHECK(differ == 0);
    CHECK(std::memcmp(a.refs.data(), b.refs.data(), a.refs.size() * sizeof(std::uint32_t)) == 0);
    CHECK(std::memcmp(a.orders.data(), b.orders.data(), a.orders.size()) == 0);
    CHECK(a.depth == b.depth);
    CHECK(a.leaves == b.leaves);
}
}  // namespace

TEST_CASE("compact: built from the tree's triangle numbers alone, the same layout byte for byte, and a smaller peak") {
    const engine::Mesh mesh = testing::procedural_shapes();
    check_ids_only_source<4>(mesh);
#if XSIMD_WITH_AVX2
    check_ids_only_source<8>(mesh);
#endif
#if XSIMD_WITH_AVX512F
    check_ids_only_source<16>(mesh);
#endif
    // The compact build never holds the wide layout's vertex blocks: its peak is below the
    // default build's, at every width.
    for (const std::uint32_t width : {4u, 8u, 16u}) {
        CAPTURE(width);
        accel::BuildConfig cfg;
        cfg.wide.width = width;
        accel::BuildConfig compact_cfg = cfg;
        compact_cfg.compact = true;
        const auto wide = accel::make_accel(accel::AccelKind::bvh_sah, mesh.view(), cfg);
        const auto compact = accel::make_accel(accel::AccelKind::bvh_sah, mesh.view(), compact_cfg);
        CAPTURE(wide->stats().build_peak_bytes);
        CAPTURE(compact->stats().build_peak_bytes);
        CHECK(compact->stats().build_peak_bytes < wide->stats().build_peak_bytes);
    }
}
