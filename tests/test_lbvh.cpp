// lbvh: build invariants, both hierarchy methods giving the same tree, agreement with the brute
// oracle (closest and any hit; coherent, incoherent and random rays), degenerate inputs,
// determinism at 1 and 2 threads, and watertightness.
#include "accel/factory/make_accel.h"
#include "accel/structures/brute_accel.h"
#include "accel/structures/bvh_accel.h"
#include "accel/lbvh/lbvh_build.h"
#include "accel/lbvh/morton.h"
#include "engine/obj_loader.h"
#include "engine/procedural.h"
#include "testing.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cfloat>
#include <cmath>
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <limits>

using namespace arbor;
using accel::BinaryBvh;
using accel::Hit;
using accel::LbvhOptions;
using accel::MortonSort;
using accel::Ray;
using accel::RadixTreeMethod;
using accel::Vec3f;

namespace {

BinaryBvh build(const engine::Mesh& mesh, const accel::BvhBuildConfig& cfg, const LbvhOptions& opt) {
    return accel::build_lbvh(accel::make_prim_refs(mesh.view()), cfg, opt);
}

/// Bit-identical nodes and leaf order.
bool same_tree(const BinaryBvh& a, const BinaryBvh& b) {
    return a.nodes.size() == b.nodes.size() && a.prim_ids == b.prim_ids &&
           std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(accel::BvhBuildNode)) == 0;
}

/// The same nodes, and the same triangles in each leaf in any order. (Box bounds compare with ==:
/// the union of a leaf's boxes may pick +0 or -0 depending on the order.)
bool same_tree_up_to_leaf_order(const BinaryBvh& a, BinaryBvh b) {
    if (a.nodes.size() != b.nodes.size() || a.prim_ids.size() != b.prim_ids.size()) return false;
    for (std::size_t i = 0; i < a.nodes.size(); ++i) {
        const auto &x = a.nodes[i], &y = b.nodes[i];
        if (x.first != y.first || x.count != y.count) return false;
        if (!(x.box.lo.x == y.box.lo.x && x.box.lo.y == y.box.lo.y && x.box.lo.z == y.box.lo.z &&
              x.box.hi.x == y.box.hi.x && x.box.hi.y == y.box.hi.y && x.box.hi.z == y.box.hi.z))
            return false;
    }
    BinaryBvh sorted = a;
    for (const auto& n : a.nodes)
        if (n.is_leaf()) {
            std::sort(sorted.prim_ids.begin() + n.first, sorted.prim_ids.begin() + n.first + n.count);
            std::sort(b.prim_ids.begin() + n.first, b.prim_ids.begin() + n.first + n.count);
        }
    return sorted.prim_ids == b.prim_ids;
}

/// Every variant (both hierarchies, 30-bit codes, 63-bit codes sorted in full or refined, both
/// digit widths unless `quick`) is valid; for a code width, all variants build the same tree bit
/// for bit (the refined 63-bit order may permute the triangles inside a leaf). Returns the default
/// build.
BinaryBvh check_all_variants(const engine::Mesh& mesh, const accel::BvhBuildConfig& cfg, bool quick = false) {
    BinaryBvh result, first30, first63, sah_first;
    for (MortonSort codes : {MortonSort::bits30, MortonSort::bits63, MortonSort::bits63_refined}) {
        for (RadixTreeMethod method : {RadixTreeMethod::top_down, RadixTreeMethod::karras}) {
            for (int digits : {8, 11}) {
                if (quick && digits != LbvhOptions{}.digit_bits) continue;
                CAPTURE(int(codes));
                CAPTURE(int(method));
                CAPTURE(digits);
                BinaryBvh bvh = build(mesh, cfg, {method, codes, digits});
                CHECK(accel::validate_bvh(bvh, mesh.view(), cfg.max_leaf_size) == "");
                BinaryBvh& first = codes == MortonSort::bits30 ? first30 : first63;
                if (first.nodes.empty()) first = bvh;
                else if (codes == MortonSort::bits63_refined) CHECK(same_tree_up_to_leaf_order(first, bvh));
                else CHECK(same_tree(first, bvh));
                if (codes == LbvhOptions{}.codes && method == LbvhOptions{}.hierarchy && digits == LbvhOptions{}.digit_bits)
                    result = bvh;
                if (codes == MortonSort::bits63_refined && digits == 8) {  // SAH collapse: valid, both methods agree
                    BinaryBvh sah = build(mesh, cfg, {method, codes, digits, true});
                    CHECK(accel::validate_bvh(sah, mesh.view(), cfg.max_leaf_size) == "");
                    CHECK(accel::bvh_tree_stats(sah).sah_cost <= accel::bvh_tree_stats(bvh).sah_cost * 1.000001);
                    if (method == RadixTreeMethod::top_down) sah_first = std::move(sah);
                    else CHECK(same_tree(sah_first, sah));
                }
            }
        }
    }
    return result;
}

std::unique_ptr<accel::Accel> make_lbvh(const engine::Mesh& mesh, const accel::BuildConfig& cfg = {}) {
    return accel::make_accel(accel::AccelKind::lbvh, mesh.view(), cfg);
}

/// Closest and any hit of `accel` against brute on `rays`: 100% agreement by the rayfile.md rule.
void check_oracle(const engine::Mesh& mesh, const accel::Accel& accel, const std::vector<Ray>& rays) {
    accel::BruteAccel brute(mesh.view());
    std::vector<Hit> ref(rays.size()), got(rays.size()), any(rays.size());
    brute.trace(rays, ref, {accel::Query::closest, accel::TracePath::scalar});
    accel.trace(rays, got, {accel::Query::closest, accel::TracePath::scalar});
    accel.trace(rays, any, {accel::Query::any, accel::TracePath::scalar});
    CHECK(testing::count_disagreements(ref, got) == 0);
    CHECK(testing::count_occlusion_disagreements(any, ref) == 0);
    for (std::size_t i = 0; i < rays.size(); ++i)
        if (any[i].is_hit()) CHECK((any[i].t >= rays[i].tnear && any[i].t <= rays[i].tfar));
}

/// The three ray kinds of the issue, `n` of each (the camera grid rounded to a square).
void check_oracle_all_kinds(const engine::Mesh& mesh, const accel::Accel& accel, std::size_t n, std::uint32_t seed) {
    const int side = std::max(2, int(std::sqrt(double(n))));
    check_oracle(mesh, accel, testing::camera_rays(mesh.bounds, side, side));
    check_oracle(mesh, accel, testing::random_rays_inside(mesh.bounds, n, seed));
    check_oracle(mesh, accel, testing::random_rays_into(mesh.bounds, n, seed + 1));
}

}  // namespace

TEST_CASE("lbvh: valid trees on procedural meshes, Karras and top-down build the same tree") {
    engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 4, 0.1f, 3);
    mesh.append(engine::make_torus({3, 0, 0}, 1.0f, 0.25f, 30, 10));
    mesh.append(engine::make_box({-5, -5, -5}, {-4, 6, -4.5f}));
    for (std::uint32_t leaf : {1u, 4u, 7u}) {
        CAPTURE(leaf);
        accel::BvhBuildConfig cfg;
        cfg.max_leaf_size = leaf;
        cfg.parallel_threshold = 256;
        const BinaryBvh bvh = check_all_variants(mesh, cfg);
        const auto stats = accel::bvh_tree_stats(bvh);
        CHECK(stats.max_leaf_size <= leaf);
        CHECK(stats.leaves * leaf >= mesh.triangle_count());
        CHECK(stats.max_depth < 64);
        CHECK(stats.sah_cost > 1.0);
    }
}

TEST_CASE("lbvh: agrees with brute on procedural meshes") {
    const engine::Mesh mesh = engine::make_icosphere({0.5f, -1.0f, 2.0f}, 1.5f, 3, 0.1f, 4);
    for (std::uint32_t leaf : {1u, 4u, 8u}) {
        accel::BuildConfig cfg;
        cfg.bvh.max_leaf_size = leaf;
        const auto lbvh = make_lbvh(mesh, cfg);
        CHECK(lbvh->kind() == accel::AccelKind::lbvh);
        CHECK(lbvh->stats().nodes > 1);
        CHECK(lbvh->stats().build_peak_bytes > 0);
        check_oracle_all_kinds(mesh, *lbvh, 1500, leaf);
    }
}

TEST_CASE("lbvh: shared models: invariants, both methods identical, agreement with brute") {
    const auto paths = testing::model_paths();
    for (const std::string& path : paths) {
        CAPTURE(path);
        engine::Warnings warnings;
        const engine::Mesh mesh = engine::load_obj(path, warnings);
        check_all_variants(mesh, {}, true);
        const auto lbvh = make_lbvh(mesh);
        // Brute costs rays x triangles: about 1M triangle tests per ray kind and model.
        const std::size_t rays = std::clamp<std::size_t>(1'000'000 / mesh.triangle_count(), 30, 1000);
        check_oracle_all_kinds(mesh, *lbvh, rays, 7);
    }
}

TEST_CASE("lbvh: all centroids equal (100k copies of one triangle): bounded depth, no giant leaf") {
    engine::Mesh mesh;
    mesh.add_vertex({0, 0, 0}), mesh.add_vertex({1, 0, 0}), mesh.add_vertex({0, 1, 0});
    const std::size_t n = 100000;
    for (std::size_t i = 0; i < n; ++i) mesh.add_triangle(0, 1, 2);
    mesh.compute_bounds();
    const accel::BvhBuildConfig cfg;
    for (RadixTreeMethod method : {RadixTreeMethod::top_down, RadixTreeMethod::karras}) {
        const BinaryBvh bvh = build(mesh, cfg, {method, MortonSort::bits63_refined, 8});
        CHECK(accel::validate_bvh(bvh, mesh.view(), cfg.max_leaf_size) == "");
        const auto stats = accel::bvh_tree_stats(bvh);
        CHECK(stats.max_depth <= 17);  // ceil(log2(100000)) = 17: the position bits split the run
        CHECK(stats.max_leaf_size <= 4);
        CHECK(stats.leaves >= n / 4);
        // The root splits on the highest differing position bit: 65536 | 34464, not 1 | n - 1.
        const auto& left = bvh.nodes[bvh.nodes[0].first];
        CHECK_FALSE(left.is_leaf());
    }
    const auto lbvh = make_lbvh(mesh);
    std::vector<Ray> rays;
    for (int i = 0; i < 8; ++i) rays.push_back({{0.1f * float(i), 0.1f, 5}, 0, {0, 0, -1}, INFINITY});
    rays.push_back({{2, 2, 5}, 0, {0, 0, -1}, INFINITY});  // misses
    check_oracle(mesh, *lbvh, rays);
}

TEST_CASE("lbvh: a dense cluster in a huge scene: the refined 63-bit order is the full 63-bit order") {
    // 5120 triangles in one 30-bit cell: one long run of equal top bits (radix-refined), plus a few
    // short runs of big triangles; the 30-bit tree can only split that run by position.
    engine::Mesh mesh = engine::make_icosphere({0.9765625f, 0.9765625f, 0.9765625f}, 1e-3f, 4);
    for (float s : {-1000.0f, 1000.0f})
        for (float t : {-1000.0f, 1000.0f}) mesh.append(engine::make_box({s, t, s}, {s + 1, t + 1, s + 1}));
    mesh.compute_bounds();
    const auto refs = accel::make_prim_refs(mesh.view());
    const accel::MortonQuantizer q10(refs.centroid_bounds, 10);
    std::size_t in_cell = 0;
    for (std::size_t i = 0; i < refs.size(); ++i) in_cell += q10.code30(refs.centroid(i)) == q10.code30(refs.centroid(0));
    CHECK(in_cell == 5120);
    const BinaryBvh full = accel::build_lbvh(refs, {}, {RadixTreeMethod::top_down, MortonSort::bits63, 8});
    const BinaryBvh refined = accel::build_lbvh(refs, {}, {RadixTreeMethod::top_down, MortonSort::bits63_refined, 8});
    const BinaryBvh karras = accel::build_lbvh(refs, {}, {RadixTreeMethod::karras, MortonSort::bits63_refined, 11});
    const BinaryBvh coarse = accel::build_lbvh(refs, {}, {RadixTreeMethod::top_down, MortonSort::bits30, 8});
    CHECK(accel::validate_bvh(refined, mesh.view(), 4) == "");
    CHECK(same_tree_up_to_leaf_order(full, refined));
    CHECK(same_tree(refined, karras));
    CHECK(accel::bvh_tree_stats(refined).sah_cost < accel::bvh_tree_stats(coarse).sah_cost);
    check_oracle_all_kinds(mesh, *make_lbvh(mesh), 300, 12);
}

TEST_CASE("lbvh: degenerate inputs: one plane, one triangle, zero-area and sliver triangles") {
    SUBCASE("all triangles in one plane (zero-extent axis)") {
        engine::Mesh mesh;
        for (int i = 0; i <= 40; ++i)
            for (int j = 0; j <= 40; ++j) mesh.add_vertex({float(i), float(j), 2.0f});
        for (std::uint32_t i = 0; i < 40; ++i)
            for (std::uint32_t j = 0; j < 40; ++j) {
                const std::uint32_t a = i * 41 + j;
                mesh.add_triangle(a, a + 41, a + 1);
                mesh.add_triangle(a + 1, a + 41, a + 42);
            }
        mesh.compute_bounds();
        check_all_variants(mesh, {});
        const auto lbvh = make_lbvh(mesh);
        check_oracle(mesh, *lbvh, testing::random_rays_into(mesh.bounds, 2000, 5));
        // Rays inside the plane (tangent) and through shared vertices, axis-parallel with -0.
        std::vector<Ray> rays;
        for (int i = 0; i < 40; ++i) {
            rays.push_back({{float(i), float(i % 7), 3.0f}, 0, {-0.0f, 0.0f, -1.0f}, INFINITY});
            rays.push_back({{-1.0f, float(i) + 0.5f, 2.0f}, 0, {1.0f, -0.0f, 0.0f}, INFINITY});
        }
        check_oracle(mesh, *lbvh, rays);
    }
    SUBCASE("a single triangle") {
        engine::Mesh mesh;
        mesh.add_vertex({0, 0, 0}), mesh.add_vertex({1, 0, 0}), mesh.add_vertex({0, 1, 0});
        mesh.add_triangle(0, 1, 2);
        mesh.compute_bounds();
        const BinaryBvh bvh = check_all_variants(mesh, {});
        REQUIRE(bvh.nodes.size() == 1);
        CHECK(bvh.nodes[0].count == 1);
        const auto lbvh = make_lbvh(mesh);
        check_oracle(mesh, *lbvh, testing::random_rays_into(mesh.bounds, 500, 6));
    }
    SUBCASE("zero-area, repeated-vertex and sliver triangles among normal ones") {
        engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 2);
        const std::uint32_t a = mesh.add_vertex({0, 0, 0}), b = mesh.add_vertex({1, 1, 1}),
                            c = mesh.add_vertex({2, 2, 2}), d = mesh.add_vertex({0.5f, 0.5f, 0.5f + 1e-7f});
        for (int i = 0; i < 50; ++i) {
            mesh.add_triangle(a, b, c);  // collinear
            mesh.add_triangle(a, a, b);  // repeated vertex
            mesh.add_triangle(a, c, d);  // sliver
        }
        mesh.compute_bounds();
        check_all_variants(mesh, {});
        check_oracle_all_kinds(mesh, *make_lbvh(mesh), 1500, 8);
    }
}

TEST_CASE("lbvh: coordinates near +-FLT_MAX") {
    engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 1);
    const float big = 3e38f;
    for (float s : {-1.0f, 1.0f}) {
        const std::uint32_t a = mesh.add_vertex({s * big, -1, -1}), b = mesh.add_vertex({s * big, 1, -1}),
                            c = mesh.add_vertex({s * big, 0, 1});
        mesh.add_triangle(a, b, c);
        const std::uint32_t d = mesh.add_vertex({-big, -big, s * big}), e = mesh.add_vertex({big, -big, s * big}),
                            f = mesh.add_vertex({0, big, s * big});
        mesh.add_triangle(d, e, f);
    }
    mesh.compute_bounds();
    const BinaryBvh bvh = check_all_variants(mesh, {});
    for (const auto& node : bvh.nodes) {
        CHECK(std::isfinite(node.box.lo.x));
        CHECK(std::isfinite(node.box.hi.z));
    }
    const auto lbvh = make_lbvh(mesh);
    std::vector<Ray> rays;
    for (float s : {-1.0f, 1.0f}) {
        rays.push_back({{0, 0, 0}, 0, {s, 0, 0}, INFINITY});              // to the far +-x triangles
        rays.push_back({{0, 0, 0}, 0, {0, 0, s}, INFINITY});              // to the huge +-z ones
        rays.push_back({{0, 0, 0}, 2, {0, 0.1f * s, s}, INFINITY});       // past the sphere
        rays.push_back({{0, 0, s * 5}, 0, {0, 0, -s}, INFINITY});         // onto the sphere
    }
    check_oracle(mesh, *lbvh, rays);
    // Far origins, axis-parallel: the hit is at t = 1e38, but the watertight kernel's t overflows to
    // +inf (found here; brute reports the same). A t of +inf is the miss record's, so the kernel
    // reports a miss there (ray_triangle.h); the structure must still give brute's answer.
    accel::BruteAccel brute(mesh.view());
    for (float s : {-1.0f, 1.0f}) {
        const Ray far{{s * 2e38f, 0, 0}, 0, {s, 0.0f, -0.0f}, INFINITY};
        Hit ref, got;
        brute.trace({&far, 1}, {&ref, 1}, {accel::Query::closest, accel::TracePath::scalar});
        lbvh->trace({&far, 1}, {&got, 1}, {accel::Query::closest, accel::TracePath::scalar});
        CHECK(got.is_hit() == ref.is_hit());
        CHECK(got.prim == ref.prim);
    }
    check_oracle(mesh, *lbvh, testing::random_rays_inside(engine::make_box({-3, -3, -3}, {3, 3, 3}).bounds, 1000, 9));
}

TEST_CASE("lbvh: non-finite triangles are dropped and counted") {
    engine::Mesh mesh = engine::make_torus({0, 0, 0}, 1.0f, 0.3f, 24, 12);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const std::uint32_t p = mesh.add_vertex({nan, 0, 0}), q = mesh.add_vertex({0, inf, 0}), r = mesh.add_vertex({0, 0, -inf});
    for (int i = 0; i < 5; ++i) mesh.add_triangle(p, 0, 1), mesh.add_triangle(2, q, 3), mesh.add_triangle(4, 5, r);
    const std::size_t finite = 24 * 12 * 2;
    const auto refs = accel::make_prim_refs(mesh.view());
    const BinaryBvh bvh = accel::build_lbvh(refs, {});
    CHECK(bvh.dropped_nonfinite == 15);
    CHECK(bvh.prim_ids.size() == finite);
    CHECK(accel::validate_bvh(bvh, mesh.view(), 4) == "");
    const auto lbvh = make_lbvh(mesh);
    CHECK(lbvh->stats().dropped_nonfinite == 15);
    CHECK(lbvh->stats().triangles == finite + 15);
    mesh.compute_bounds();
    accel::Bounds box{{-2, -1, -2}, {2, 1, 2}};
    check_oracle(mesh, *lbvh, testing::random_rays_into(box, 1500, 10));

    // Only non-finite triangles: an empty tree, and every ray misses.
    engine::Mesh bad;
    bad.add_vertex({nan, 0, 0}), bad.add_vertex({1, 0, 0}), bad.add_vertex({0, 1, 0});
    bad.add_triangle(0, 1, 2);
    const BinaryBvh empty = accel::build_lbvh(accel::make_prim_refs(bad.view()), {});
    CHECK(empty.nodes.empty());
    CHECK(empty.dropped_nonfinite == 1);
    CHECK_FALSE(static_cast<const accel::BvhAccel&>(*make_lbvh(bad)).trace_one({{0, 0, 1}, 0, {0, 0, -1}, INFINITY}, accel::Query::closest).is_hit());
}

TEST_CASE("lbvh: bit-identical tree with 1 and 2 threads") {
    engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 5, 0.2f, 9);  // 20480 triangles
    engine::Mesh copies;
    copies.add_vertex({0, 0, 0}), copies.add_vertex({0.01f, 0, 0}), copies.add_vertex({0, 0.01f, 0});
    for (int i = 0; i < 5000; ++i) copies.add_triangle(0, 1, 2);  // a long run of equal codes
    mesh.append(copies);
    accel::BvhBuildConfig cfg;
    cfg.parallel_threshold = 64;
    for (MortonSort codes : {MortonSort::bits30, MortonSort::bits63, MortonSort::bits63_refined}) {
        for (RadixTreeMethod method : {RadixTreeMethod::top_down, RadixTreeMethod::karras}) {
            CAPTURE(int(codes));
            CAPTURE(int(method));
            auto run = [&](int threads) {
                tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
                return build(mesh, cfg, {method, codes, 8});
            };
            const BinaryBvh one = run(1), two = run(2);
            CHECK(same_tree(one, two));
            CHECK(accel::validate_bvh(two, mesh.view(), cfg.max_leaf_size) == "");
        }
    }
}

TEST_CASE("lbvh: watertight closed mesh: every ray from inside hits, aimed at vertices and edges too") {
    for (int seed = 1; seed <= 3; ++seed) {
        const Vec3f center{1000.0f * float(seed - 2), 3.0f, -7.0f};
        const engine::Mesh mesh = engine::make_icosphere(center, 2.0f, 3, 0.2f, std::uint32_t(seed));
        const auto lbvh = make_lbvh(mesh);
        std::vector<Ray> rays;
        const auto v = mesh.view();
        const Vec3f origins[] = {center, center + Vec3f{0.31f, -0.17f, 0.05f}, center + Vec3f{-0.5f, 0.5f, 0.25f}};
        for (const Vec3f& o : origins)
            for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
                const Vec3f a = v.corner(t, 0), b = v.corner(t, 1), c = v.corner(t, 2);
                for (const Vec3f& target : {a, (a + b) * 0.5f, (b + c) * 0.5f, a * 0.75f + c * 0.25f})
                    rays.push_back({o, 0.0f, target - o, std::numeric_limits<float>::infinity()});
            }
        std::vector<Hit> hits(rays.size()), any(rays.size());
        lbvh->trace(rays, hits, {accel::Query::closest, accel::TracePath::scalar});
        lbvh->trace(rays, any, {accel::Query::any, accel::TracePath::scalar});
        std::size_t leaks = 0, any_leaks = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) leaks += !hits[i].is_hit(), any_leaks += !any[i].is_hit();
        CAPTURE(seed);
        CHECK(leaks == 0);
        CHECK(any_leaks == 0);
        std::size_t off = 0;
        for (std::size_t i = 0; i < rays.size() / 3; ++i) off += std::fabs(hits[i].t - 1.0f) > 1e-4f;
        CHECK(off == 0);
    }
}
