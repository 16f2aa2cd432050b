// The SIMD traversal paths (single, packet, best) of bvh-median, bvh-sah and lbvh at every width
// against their scalar path and brute: every shared model with primary, shadow, diffuse and random
// rays (engine/ray_gen.h); then the stiff cases: a watertight jittered icosphere seen from inside,
// axis-parallel rays with +-0 components on an integer grid, NaN/Inf/zero rays, partial packets,
// mixed-sign packets, and identical answers with 1 and 2 threads.
#include "accel/factory/make_accel.h"
#include "accel/interface/coherence.h"
#include "engine/obj_loader.h"
#include "engine/procedural.h"
#include "ray_kinds.h"
#include "wide_check.h"

#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

using namespace arbor;
using accel::Hit;
using accel::Ray;
using accel::Vec3f;

namespace {

#if defined(ARBOR_SANITIZED_BUILD)
constexpr std::size_t rays_per_kind = 160;
#else
constexpr std::size_t rays_per_kind = 1024;
#endif

void check_mesh(const engine::Mesh& mesh, const std::vector<Ray>& rays, std::size_t brute_rays, accel::BuildConfig cfg = {},
                std::size_t chunk = 1024) {
    const accel::BruteAccel brute(mesh.view());
    const auto sample = testing::spread(rays.size(), brute_rays);
    std::vector<Ray> sub;
    for (std::size_t i : sample) sub.push_back(rays[i]);
    const auto ref = testing::brute_answers(brute, sub);
    for (const auto& b : testing::all_wide_bvhs(mesh.view(), cfg)) {
        CAPTURE(b.name);
        CHECK(testing::check_paths(*b.accel, mesh.view(), rays, sample, ref, chunk) >= 2);
    }
}

}  // namespace

TEST_CASE("wide paths: every shared model, primary/shadow/diffuse/random rays (three shadow recipes), all structures and widths") {
    for (const auto& path : testing::model_paths()) {
        CAPTURE(path);
        engine::Warnings w;
        const engine::Mesh mesh = engine::load_obj(path, w);
        const auto tracer = accel::make_accel(accel::AccelKind::bvh_sah, mesh.view());
        // Big models get fewer rays (the sanitizer build is ~10x slower); brute sees a subset.
        const std::size_t n = mesh.triangle_count() > 30000 ? rays_per_kind / 2 : rays_per_kind;
        const auto rays = testing::ray_kinds(mesh, n, *tracer, 7);
        check_mesh(mesh, rays, testing::oracle_ray_count(mesh.triangle_count(), 32, 1024));
    }
}

TEST_CASE("wide paths: procedural meshes at leaf sizes 1, 4 and 40") {
    const engine::Mesh mesh = testing::procedural_shapes();
    auto rays = testing::random_rays_into(mesh.bounds, 300, 3);
    const auto inside = testing::random_rays_inside(mesh.bounds, 300, 4);
    const auto cam = testing::camera_rays(mesh.bounds, 24, 24);
    rays.insert(rays.end(), inside.begin(), inside.end());
    rays.insert(rays.end(), cam.begin(), cam.end());
    for (const std::uint32_t leaf : {1u, 4u, 40u}) {
        accel::BuildConfig cfg;
        cfg.bvh.max_leaf_size = leaf;
        CAPTURE(leaf);
        check_mesh(mesh, rays, rays.size(), cfg);
    }
}

TEST_CASE("wide paths: watertight jittered icosphere seen from inside: no ray leaks on any path") {
    const Vec3f center{1000.0f, 3.0f, -7.0f};
    const engine::Mesh mesh = engine::make_icosphere(center, 2.0f, 3, 0.2f, 2);
    const auto v = mesh.view();
    std::vector<Ray> rays;
    for (const Vec3f& o : {center, center + Vec3f{0.31f, -0.17f, 0.05f}})
        for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
            const Vec3f a = v.corner(t, 0), b = v.corner(t, 1), c = v.corner(t, 2);
            for (const Vec3f& target : {a, (a + b) * 0.5f, (b + c) * 0.5f, a * 0.75f + c * 0.25f})
                rays.push_back({o, 0.0f, target - o, INFINITY});
        }
    for (const auto& b : testing::all_wide_bvhs(v)) {
        for (const auto path : testing::simd_paths(*b.accel)) {
            std::vector<Hit> hits(rays.size()), any(rays.size());
            accel::trace_parallel(*b.accel, rays, hits, accel::Query::closest, path);
            accel::trace_parallel(*b.accel, rays, any, accel::Query::any, path);
            std::size_t leaks = 0, any_leaks = 0;
            for (std::size_t i = 0; i < rays.size(); ++i) leaks += !hits[i].is_hit(), any_leaks += !any[i].is_hit();
            CAPTURE(b.name);
            CAPTURE(accel::to_string(path));
            CHECK(leaks == 0);
            CHECK(any_leaks == 0);
        }
    }
}

TEST_CASE("wide paths: axis-parallel rays with +-0 components on an integer grid, rays in the grid plane") {
    // A 6x6 grid of unit squares in z = 0 (two triangles each) and a second grid in x = 3.
    engine::Mesh mesh;
    for (int plane = 0; plane < 2; ++plane)
        for (int i = 0; i < 6; ++i)
            for (int j = 0; j < 6; ++j) {
                const auto base = std::uint32_t(mesh.vertex_count());
                for (const auto& [di, dj] : {std::pair{0, 0}, std::pair{1, 0}, std::pair{1, 1}, std::pair{0, 1}}) {
                    const float a = float(i + di), b = float(j + dj);
                    mesh.add_vertex(plane == 0 ? Vec3f{a, b, 0.0f} : Vec3f{3.0f, a, b - 3.0f});
                }
                mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
            }
    mesh.compute_bounds();
    std::vector<Ray> rays;
    for (int i = 0; i <= 12; ++i)
        for (int j = 0; j <= 12; ++j) {
            const float a = float(i) * 0.5f, b = float(j) * 0.5f;  // vertices, edges and centres
            for (const float zero : {0.0f, -0.0f})
                for (const float s : {1.0f, -1.0f}) {
                    rays.push_back({{a, b, -4.0f * s}, 0.0f, {zero, zero, s}, INFINITY});
                    rays.push_back({{-4.0f * s, a, b - 3.0f}, 0.0f, {s, zero, zero}, INFINITY});
                    rays.push_back({{a, -4.0f * s, b * 0.5f}, 0.0f, {zero, s, zero}, INFINITY});  // grazes x = 3
                    rays.push_back({{a, b, 0.0f}, 0.0f, {s, zero, zero}, INFINITY});            // in the plane z = 0
                    rays.push_back({{a, b, 0.0f}, 0.0f, {zero, zero, s}, 0.5f});                // starts on the grid
                }
        }
    check_mesh(mesh, rays, rays.size());
    check_mesh(mesh, rays, rays.size(), {}, 7);  // small chunks: partial packets everywhere
}

TEST_CASE("wide paths: NaN, Inf, zero and inactive rays miss, partial and mixed-sign packets") {
    engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 2);
    mesh.append(engine::make_box({-3, -3, -3}, {-2, -2, -2}));
    const float nan = NAN, inf = INFINITY;
    std::vector<Ray> bad{{{nan, 0, 0}, 0, {1, 0, 0}, inf},  {{0, 0, -5}, 0, {0, nan, 1}, inf}, {{inf, 0, 0}, 0, {-1, 0, 0}, inf},
                         {{0, 0, -5}, 0, {0, 0, inf}, inf}, {{0, 0, -5}, 0, {0, 0, 0}, inf},   {{0, 0, -5}, 0, {-0.0f, 0, -0.0f}, inf},
                         {{0, 0, -5}, nan, {0, 0, 1}, inf}, {{0, 0, -5}, 0, {0, 0, 1}, nan},   {{0, 0, -5}, 3, {0, 0, 1}, 2},
                         {{0, 0, -5}, inf, {0, 0, 1}, inf}};
    // Mixed-sign packets: neighbours point in opposite directions, some lanes bad.
    std::vector<Ray> rays;
    for (int i = 0; i < 300; ++i) {
        const float s = (i % 2) ? 1.0f : -1.0f, x = float(i % 17) * 0.1f - 0.8f, y = float(i % 13) * 0.12f - 0.7f;
        rays.push_back({{x, y, -5.0f * s}, 0.0f, {0.01f * float(i % 5) * s, -0.02f * s, s}, INFINITY});
        if (i % 7 == 0) rays.push_back(bad[std::size_t(i / 7) % bad.size()]);
        if (i % 11 == 0) rays.push_back({{-5.0f * s, x, y}, 0.0f, {s, 0.0f, -0.0f}, INFINITY});
    }
    for (const auto& b : testing::all_wide_bvhs(mesh.view()))
        for (const auto path : testing::simd_paths(*b.accel)) {
            std::vector<Hit> hits(bad.size());
            b.accel->trace(bad, hits, {accel::Query::closest, path});
            for (const Hit& h : hits) CHECK(!h.is_hit());
            b.accel->trace(bad, hits, {accel::Query::any, path});
            for (const Hit& h : hits) CHECK(!h.is_hit());
        }
    for (const std::size_t chunk : {1u, 3u, 16u, 17u, 64u, 1024u}) {
        CAPTURE(chunk);
        check_mesh(mesh, rays, rays.size(), {}, chunk);
    }
}

TEST_CASE("wide paths: identical answers with 1 and 2 threads") {
    const engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 3, 0.2f, 4);
    auto rays = testing::random_rays_into(mesh.bounds, 2000, 8);
    const auto cam = testing::camera_rays(mesh.bounds, 48, 48);
    rays.insert(rays.end(), cam.begin(), cam.end());
    for (const auto& b : testing::all_wide_bvhs(mesh.view()))
        for (const auto path : testing::simd_paths(*b.accel))
            for (const auto q : {accel::Query::closest, accel::Query::any}) {
                std::vector<Hit> one(rays.size()), two(rays.size());
                {
                    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
                    accel::trace_parallel(*b.accel, rays, one, q, path, 64);
                }
                {
                    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
                    accel::trace_parallel(*b.accel, rays, two, q, path, 64);
                }
                CAPTURE(b.name);
                CHECK(std::memcmp(one.data(), two.data(), one.size() * sizeof(Hit)) == 0);
            }
}

TEST_CASE("coherence measure: tiles of camera rays are coherent, random rays and mixed octants are not (unless asked)") {
    const accel::Bounds b{{-1, -1, -1}, {1, 1, 1}};
    const auto cam = testing::camera_rays(b, 64, 16);  // one origin; the image does not straddle an axis
    const auto inside = testing::random_rays_inside(b, 1024, 5);
    CHECK(accel::coherent_fraction(cam, 16, 0.1f, 1000) > 0.7);
    CHECK(accel::coherent_fraction(inside, 16, 0.1f, 1000) == 0.0);
    CHECK(accel::coherent_fraction(cam, 16, 0.1f) == doctest::Approx(accel::coherent_fraction(cam, 16, 0.1f, 1000)).epsilon(0.3));
    // A group whose origins are farther apart than `spread` is not coherent; neither is one with two octants.
    std::vector<Ray> far(16, Ray{{0, 0, 0}, 0.0f, {1, 1, 1}, INFINITY});
    far[5].org = {0.5f, 0, 0};
    CHECK(accel::coherent_fraction(far, 16, 0.1f) == 0.0);
    CHECK(accel::coherent_fraction(far, 16, 1.0f) == 1.0);
    std::vector<Ray> mixed(16, Ray{{0, 0, 0}, 0.0f, {1, 1, 1}, INFINITY});
    mixed[3].dir.y = -0.0f;  // -0 counts as negative, as in the slab test
    CHECK(accel::coherent_fraction(mixed, 16, 1.0f) == 0.0);
    // Not asking for one octant: origins close together are enough (diffuse bounces from a tile).
    CHECK(accel::coherent_fraction(mixed, 16, 1.0f, 8, false) == 1.0);
    CHECK(accel::coherent_fraction(far, 16, 0.1f, 8, false) == 0.0);
    CHECK(accel::coherent_fraction(inside, 16, 0.1f, 1000, false) == 0.0);
    // Untraceable rays do not count; no traceable ray at all gives 0.
    mixed[3].dir = {0, 0, 0};
    CHECK(accel::coherent_fraction(mixed, 16, 1.0f) == 1.0);
    CHECK(accel::coherent_fraction(std::vector<Ray>(20, Ray{{0, 0, 0}, 0.0f, {0, 0, 0}, 1.0f}), 16, 1.0f) == 0.0);
    CHECK(accel::coherent_fraction({}, 16, 1.0f) == 0.0);
}

TEST_CASE("best path: packets for rays that start together (one octant or not), single rays for scattered ones") {
    const engine::Mesh mesh = testing::procedural_shapes();
    accel::BuildConfig cfg;
    cfg.layouts = accel::Layouts::simd;
    const auto acc = accel::make_accel(accel::AccelKind::bvh_sah, mesh.view(), cfg);
    const accel::Bounds& b = mesh.bounds;
    // Bounces: each packet's origins within 1% of the scene, directions all over the sphere.
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), s(-1.0f, 1.0f);
    std::vector<Ray> bounces;
    const Vec3f ext = b.hi - b.lo;
    for (int g = 0; g < 64; ++g) {
        const Vec3f at{b.lo.x + u(rng) * ext.x, b.lo.y + u(rng) * ext.y, b.lo.z + u(rng) * ext.z};
        for (int i = 0; i < 16; ++i)
            bounces.push_back({at + 0.005f * ext * Vec3f{u(rng), u(rng), u(rng)}, 0.0f, Vec3f{s(rng), s(rng), s(rng)}, INFINITY});
    }
    const accel::PathChoice c = accel::choose_path(acc->offer(), bounces, {});
    CHECK(c.path == accel::TracePath::packet);
    CHECK(accel::path_reason(c).find("start together") != std::string::npos);
    CHECK(accel::choose_path(acc->offer(), testing::camera_rays(b, 64, 16), {}).path == accel::TracePath::packet);
    CHECK(accel::choose_path(acc->offer(), testing::random_rays_inside(b, 1024, 5), {}).path == accel::TracePath::single);
    // Shadow rays from scattered points towards one light beyond the bounds (one octant): packets
    // for the any-hit query, single rays for the same rays as closest-hit; any-hit rays in all
    // octants stay single.
    std::vector<Ray> shadow;
    const Vec3f light = b.hi + ext;
    for (int i = 0; i < 1024; ++i) {
        const Vec3f o{b.lo.x + u(rng) * ext.x, b.lo.y + u(rng) * ext.y, b.lo.z + u(rng) * ext.z};
        shadow.push_back({o, 0.0f, light - o, 0.9999f});
    }
    accel::TraceRequest any;
    any.query = accel::Query::any;
    const accel::PathChoice sc = accel::choose_path(acc->offer(), shadow, any);
    CHECK(sc.path == accel::TracePath::packet);
    CHECK(accel::path_reason(sc).find("any-hit") != std::string::npos);
    CHECK(accel::choose_path(acc->offer(), shadow, {}).path == accel::TracePath::single);
    CHECK(accel::choose_path(acc->offer(), testing::random_rays_inside(b, 1024, 5), any).path == accel::TracePath::single);
    // A light just above the middle of the scene: the shadow rays' directions straddle the x and y
    // octant boundaries, but they all end together (tfar just short of the light), so any-hit rays
    // take packets; as closest-hit, or with tfar = inf (no shared end), single rays.
    std::vector<Ray> above, open;
    const Vec3f mid = 0.5f * (b.lo + b.hi), top{mid.x, mid.y, b.hi.z + 0.1f * ext.z};
    for (int i = 0; i < 1024; ++i) {
        const Vec3f o{b.lo.x + u(rng) * ext.x, b.lo.y + u(rng) * ext.y, b.lo.z + u(rng) * ext.z};
        above.push_back({o, 0.0f, top - o, 0.9999f});
        open.push_back({o, 0.0f, top - o, INFINITY});
    }
    CHECK(accel::coherent_fraction(above, acc->offer().packet_lanes, INFINITY) < 0.5);
    const accel::PathChoice ac = accel::choose_path(acc->offer(), above, any);
    CHECK(ac.path == accel::TracePath::packet);
    CHECK(accel::path_reason(ac).find("end within") != std::string::npos);
    CHECK(accel::choose_path(acc->offer(), above, {}).path == accel::TracePath::single);
    CHECK(accel::choose_path(acc->offer(), open, any).path == accel::TracePath::single);
    // The policy's one-pass measure gives coherence.h's fractions on the same sample.
    const float spread = 0.05f * acc->offer().scene_diagonal;
    const std::uint32_t lanes = acc->offer().packet_lanes;
    for (const std::vector<Ray>* batch : {&bounces, &shadow, &above, &open}) {
        const accel::PathChoice m = accel::choose_path(acc->offer(), *batch, {});
        CHECK(m.coherent == accel::coherent_fraction(*batch, lanes, spread));
        if (!m.one_octant) CHECK(m.together == accel::coherent_fraction(*batch, lanes, spread, 8, false));
    }
}

namespace {
/// The policy's four fractions worked out here one ray at a time, as path_policy.h states them:
/// per sampled group (coherence_sample_step), its traceable rays share an octant / start within
/// `spread` / both / end (org + tfar * dir, every end finite) within `spread`.
struct PolicyFractions {
    double coherent = 0, together = 0, octant = 0, end_together = 0;
};
PolicyFractions policy_fractions(const std::vector<Ray>& rays, std::size_t group, float spread) {
    const std::size_t step = accel::coherence_sample_step(rays.size(), group);
    double groups = 0, coherent = 0, together = 0, octant = 0, ends = 0;
    for (std::size_t base = 0; base < rays.size(); base += step) {
        std::vector<const Ray*> live;
        for (std::size_t i = base; i < std::min(rays.size(), base + group); ++i)
            if (accel::ray_is_traceable(rays[i])) live.push_back(&rays[i]);
        if (live.empty()) continue;
        const auto octant_of = [](const Vec3f& d) {
            return int(std::signbit(d.x)) | int(std::signbit(d.y)) << 1 | int(std::signbit(d.z)) << 2;
        };
        bool one_octant = true, near = true, end_near = true;
        for (const Ray* a : live)
            for (const Ray* b : live) {
                one_octant = one_octant && octant_of(a->dir) == octant_of(b->dir);
                const Vec3f ea = a->org + a->tfar * a->dir, eb = b->org + b->tfar * b->dir;
                for (int k = 0; k < 3; ++k) {
                    near = near && a->org[k] - b->org[k] <= spread;
                    end_near = end_near && std::isfinite(ea[k]) && std::isfinite(eb[k]) && ea[k] - eb[k] <= spread;
                }
            }
        ++groups;
        coherent += one_octant && near, together += near, octant += one_octant, ends += end_near;
    }
    PolicyFractions f;
    if (groups > 0) f = {coherent / groups, together / groups, octant / groups, ends / groups};
    return f;
}
}  // namespace

TEST_CASE("policy measures: the fractions of a one-ray-at-a-time count, stiff rays and partial groups included") {
    // The policy measures whole 16-ray groups in SIMD registers (path_policy.cpp); groups cut by
    // the batch's end one ray at a time. Both must count what the rule says, whatever the rays.
    const engine::Mesh mesh = testing::procedural_shapes();
    accel::BuildConfig cfg;
    cfg.layouts = accel::Layouts::simd;
    const auto acc = accel::make_accel(accel::AccelKind::bvh_sah, mesh.view(), cfg);
    const accel::PathOffer& offer = acc->offer();
    const float spread = 0.05f * offer.scene_diagonal;
    const Vec3f lo = mesh.bounds.lo, ext = mesh.bounds.hi - mesh.bounds.lo;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), s(-1.0f, 1.0f);
    const auto point = [&] { return Vec3f{lo.x + u(rng) * ext.x, lo.y + u(rng) * ext.y, lo.z + u(rng) * ext.z}; };
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = INFINITY;
    int checked_octant = 0, checked_end = 0;
    for (int batch = 0; batch < 300; ++batch) {
        const std::size_t n = batch % 3 == 0 ? 900 : 1024;  // 900: the last sampled group is cut short
        std::vector<Ray> rays;
        while (rays.size() < n) {
            // A run of 16 rays: origins together or scattered, one octant or any, ending together
            // at a light (tfar just short of it) or not.
            const Vec3f at = point(), light = point() + ext;
            const bool together = u(rng) < 0.5f, one_octant = u(rng) < 0.5f, to_light = u(rng) < 0.5f;
            for (int i = 0; i < 16 && rays.size() < n; ++i) {
                Ray r;
                r.org = together ? at + 0.001f * ext * Vec3f{u(rng), u(rng), u(rng)} : point();
                r.dir = one_octant ? Vec3f{0.1f + u(rng), 0.1f + u(rng), -0.1f - u(rng)} : Vec3f{s(rng), s(rng), s(rng)};
                r.tnear = 0.0f;
                r.tfar = inf;
                if (to_light) r.dir = light - r.org, r.tfar = 0.9999f;
                switch (int(u(rng) * 24.0f)) {  // stiff rays, one in two
                case 0: r.org.y = nan; break;                       // untraceable
                // (untraceable rays elsewhere, going elsewhere: they must not count at all)
                case 1: r.dir.z = inf, r.org = point(); break;                              // untraceable
                case 2: r.dir = {0, 0, 0}, r.org = point(); break;                          // untraceable
                case 3: r.dir = {1e-39f, -1e-39f, 0}, r.org = point(); break;               // below FLT_MIN
                case 4: r.tnear = 2.0f, r.tfar = 1.0f, r.org = point(), r.dir = -r.dir; break;  // untraceable
                case 5: r.tfar = nan, r.org = point(); break;                               // untraceable
                case 6: r.tfar = inf; break;                        // an end that is not finite
                case 7: r.tfar = 3e38f; break;                      // an end that overflows
                case 8: r.dir.x = 0.0f, r.tfar = inf; break;        // inf * 0: a NaN end
                case 9: r.dir.y = -0.0f; break;                     // -0 counts as negative
                case 10: r.tnear = -inf; break;                     // traceable
                case 11: r.org = at; break;                         // a run's shared origin
                default: break;
                }
                rays.push_back(r);
            }
        }
        if (batch % 7 == 0)  // a sampled group with no traceable ray does not count
            for (std::size_t i = 128; i < 144; ++i) rays[i].dir = {0, 0, 0};
        const PolicyFractions want = policy_fractions(rays, offer.packet_lanes, spread);
        CAPTURE(batch);
        const accel::PathChoice c = accel::choose_path(offer, rays, {});
        CHECK(c.coherent == want.coherent);
        CHECK(c.together == (c.one_octant ? want.coherent : want.together));
        accel::TraceRequest any;
        any.query = accel::Query::any;
        const accel::PathChoice a = accel::choose_path(offer, rays, any);
        if (want.together < 0.5) {  // reported only where together does not decide
            ++checked_octant;
            CHECK(a.octant_only == want.octant);
            if (want.octant < 0.5) {
                ++checked_end;
                CHECK(a.end_together == want.end_together);
            }
        }
    }
    // Both reported fractions were compared often enough (300 batches; the counts depend on the
    // group size: 16, 8 or 4 lanes).
    MESSAGE("compared octant fractions: " << checked_octant << ", end fractions: " << checked_end);
    CHECK(checked_octant > 40);
    CHECK(checked_end > 10);
}

TEST_CASE("policy_sample: the path chosen over the gathered sample is the one chosen over the whole batch") {
    // The public API decides a batch's path from these rays only (api/queries.cpp): batches of
    // every size, coherent at some sampled groups and not at others, must get the same verdict.
    const engine::Mesh mesh = testing::procedural_shapes();
    accel::BuildConfig cfg;
    cfg.layouts = accel::Layouts::simd;
    const auto acc = accel::make_accel(accel::AccelKind::bvh_sah, mesh.view(), cfg);
    const accel::PathOffer& offer = acc->offer();
    const std::vector<Ray> camera = testing::camera_rays(mesh.bounds, 64, 64), random = testing::random_rays_inside(mesh.bounds, 4096, 9);
    for (const std::size_t n : {std::size_t(0), std::size_t(5), std::size_t(100), std::size_t(1000), std::size_t(4096)})
        for (const std::size_t cut : {std::size_t(0), n / 3, n / 2, n}) {
            std::vector<Ray> batch(camera.begin(), camera.begin() + std::ptrdiff_t(cut));
            batch.insert(batch.end(), random.begin(), random.begin() + std::ptrdiff_t(n - cut));
            std::vector<Ray> sample;
            for (const std::size_t i : accel::policy_sample(offer, n)) sample.push_back(batch[i]);
            CHECK(sample.size() <= std::size_t(8) * offer.packet_lanes);
            for (const accel::Query q : {accel::Query::closest, accel::Query::any}) {
                const accel::PathChoice all = accel::choose_path(offer, batch, {q}), some = accel::choose_path(offer, sample, {q});
                CAPTURE(n);
                CAPTURE(cut);
                CHECK(some.path == all.path);
                CHECK(some.coherent == all.coherent);
                CHECK(some.together == all.together);
                CHECK(some.octant_only == all.octant_only);
                CHECK(some.end_together == all.end_together);
            }
        }
}
