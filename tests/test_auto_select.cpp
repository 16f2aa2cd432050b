// --accel auto (accel/select/auto_select.h): the decision is deterministic and explains itself (the
// model's prediction and margin, or the probe's figures); a tiny job takes no probe; a job whose
// contenders the model cannot tell apart is probed when it can pay for it (both paths of each
// structure it builds), and the probe's pick is handed over built and traces like brute; the cost
// model's text format refuses malformed files by line; the path policy's expected offers match what
// the structures offer once built; the engine describes render and converge jobs the same way for
// the same rays.
#include "accel/factory/make_accel.h"
#include "accel/factory/memory_estimate.h"
#include "accel/structures/brute_accel.h"
#include "accel/select/auto_model.h"
#include "accel/select/auto_select.h"
#include "accel/interface/path_policy.h"
#include "engine/procedural.h"
#include "engine/render_job.h"
#include "engine/scene.h"
#include "perf/scenes.h"
#include "testing.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>

using namespace arbor;

namespace {

/// The text of a model whose lbvh traces at `lbvh_ns` per ray (packets) and `lbvh_single_ns` (single
/// rays; 0: lbvh_ns), bvh-sah at `sah_ns` (packets) and `sah_single_ns` (single rays; 0: sah_ns), and
/// both build in 1 ms per 1k triangles, with `margin`.
std::string flat_model(double lbvh_ns, double sah_ns, double margin, double sah_single_ns = 0.0,
                       double lbvh_single_ns = 0.0) {
    const double ln2 = std::log(2.0);
    auto line = [&](const char* s, const char* p, double ns) {
        return "trace " + std::string(s) + " " + p + " " + std::to_string(std::log(ns)) + " 0\n";
    };
    return "arbor-auto-model 1\nsource test\ntrace_features one coherent\nbuild_features one log2_triangles\nmargin " +
           std::to_string(margin) + "\nbuild lbvh " + std::to_string(-10 * ln2) + " " + std::to_string(ln2) +
           "\nbuild bvh-sah " + std::to_string(-10 * ln2) + " " + std::to_string(ln2) + "\n" +
           line("lbvh", "packet", lbvh_ns) + line("lbvh", "single", lbvh_single_ns > 0.0 ? lbvh_single_ns : lbvh_ns) +
           line("bvh-sah", "packet", sah_ns) +
           line("bvh-sah", "single", sah_single_ns > 0.0 ? sah_single_ns : sah_ns);
}

}  // namespace

TEST_CASE("auto: the built-in model parses and predicts every structure the benchmark times") {
    const accel::AutoModel& m = accel::builtin_auto_model();
    CHECK_FALSE(m.source().empty());
    CHECK(m.margin() > 0.0);
    const auto kinds = m.structures();
    for (const auto k : {accel::AccelKind::bvh_sah, accel::AccelKind::lbvh, accel::AccelKind::bvh_median, accel::AccelKind::kdtree}) {
        INFO(accel::to_string(k));
        CHECK(std::find(kinds.begin(), kinds.end(), k) != kinds.end());
        CHECK(m.has(k, accel::TracePath::packet));
        CHECK(m.has(k, accel::TracePath::single));
    }
    const engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 4, 0.2f, 3);
    const accel::SceneShape s = accel::scene_shape(mesh.view());
    CHECK(s.triangles == 5120);
    CHECK(s.sampled == 4096);
    CHECK(s.overlap > 0.0);
    accel::RayShape r;
    r.coherent = r.together = 1.0;
    for (const auto k : kinds) {
        const double ns = m.ns_per_ray(k, accel::TracePath::packet, s, r, 1.0);
        CHECK(std::isfinite(ns));
        CHECK(ns > 0.0);
        CHECK(m.build_ms(k, s, 1.0) > 0.0);
        // More triangles build slower (the model is fitted, but not that wrong).
        accel::SceneShape big = s;
        big.triangles = 1 << 20;
        CHECK(m.build_ms(k, big, 1.0) > m.build_ms(k, s, 1.0));
    }
}

TEST_CASE("auto: the scene's bounds skip every vertex with a non-finite coordinate, in the SIMD part and the tail") {
    // 37 vertices: more than two registers of 16 and a tail at every width.
    engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 1, 0.0f, 3);
    while (mesh.vertex_count() < 37) mesh.add_vertex({0.5f, 0.25f, -0.125f});
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const auto plain = [&] {
        accel::Bounds b;
        for (std::size_t i = 0; i < mesh.vertex_count(); ++i)
            if (std::isfinite(mesh.x[i]) && std::isfinite(mesh.y[i]) && std::isfinite(mesh.z[i]))
                b.grow(accel::Vec3f{mesh.x[i], mesh.y[i], mesh.z[i]});
        return b;
    };
    const auto same = [&](const char* what) {
        INFO(what);
        const accel::Bounds want = plain(), got = accel::scene_shape(mesh.view()).bounds;
        CHECK(got.lo.x == want.lo.x);
        CHECK(got.lo.y == want.lo.y);
        CHECK(got.lo.z == want.lo.z);
        CHECK(got.hi.x == want.hi.x);
        CHECK(got.hi.y == want.hi.y);
        CHECK(got.hi.z == want.hi.z);
    };
    same("finite");
    // A far vertex with one bad coordinate must not move the bounds; a far finite one must.
    mesh.x[3] = 1e30f, mesh.y[3] = nan;
    mesh.x[20] = -inf;
    mesh.z[36] = 1e20f, mesh.y[36] = inf;  // the tail at 16 and 8 wide
    same("non-finite coordinates");
    CHECK(accel::scene_shape(mesh.view()).bounds.hi.x < 10.0f);
    mesh.z[35] = -7e3f;  // finite, in the tail
    mesh.y[17] = 5e3f;   // finite, in a register
    same("far finite vertices");
    CHECK(accel::scene_shape(mesh.view()).bounds.lo.z == -7e3f);
    CHECK(accel::scene_shape(mesh.view()).bounds.hi.y == 5e3f);
}

TEST_CASE("auto: a model's numbers are read exactly, with comments, tabs and CRLF line ends") {
    const std::string text =
        "# a comment line\r\narbor-auto-model 1   # trailing comment\r\n"
        "source  two runs, one machine \r\n"
        "trace_features\tone coherent\r\nbuild_features one log2_threads\r\n"
        "clamp coherent 0 1\r\nmargin 0.35\r\nprefer bvh-sah 0.1\r\n"
        "trace lbvh packet 1.5 -2.25e-3\r\n\r\nbuild lbvh -0.125 7E-1\r\n";
    const accel::AutoModel m = accel::AutoModel::parse(text);
    CHECK(m.source() == "two runs, one machine \r");
    CHECK(m.margin() == 0.35);
    // (Features of 1, 0.5 and 2: every product is exact, so the sums are the same with or without
    // fused multiply-adds.)
    accel::SceneShape scene;
    accel::RayShape rays;
    rays.coherent = 0.5;
    CHECK(m.ns_per_ray(accel::AccelKind::lbvh, accel::TracePath::packet, scene, rays, 1.0) ==
          std::exp(1.5 * 1.0 + -2.25e-3 * 0.5));
    CHECK(m.build_ms(accel::AccelKind::lbvh, scene, 4.0) == std::exp(-0.125 * 1.0 + 7E-1 * 2.0));
}

TEST_CASE("auto: a malformed model is refused with the line that is wrong") {
    auto refuses = [](const std::string& text, const std::string& what) {
        INFO(text);
        try {
            (void)accel::AutoModel::parse(text);
            FAIL("parsed");
        } catch (const std::invalid_argument& e) {
            CHECK(std::string(e.what()).find(what) != std::string::npos);
        }
    };
    const std::string head = "arbor-auto-model 1\ntrace_features one coherent\nbuild_features one\n";
    refuses("", "empty");
    refuses("arbor-auto-model 2\n", "line 1");
    refuses(head + "trace lbvh packet 1\nbuild lbvh 0\n", "line 4: 1 coefficients for 2 features");
    refuses(head + "trace lbvh packet 1 x\n", "line 4: a coefficient is not a number");
    refuses(head + "trace octree packet 1 2\n", "line 4: unknown structure 'octree'");
    refuses(head + "trace lbvh best 1 2\n", "line 4: unknown path 'best'");
    refuses(head + "clamp colour 0 1\n", "line 4: unknown feature 'colour'");
    refuses(head + "frobnicate\n", "line 4: unknown keyword");
    refuses(head + "trace lbvh packet 1 2\n", "no structure has both");
    refuses(head + "prefer octree 0.1\n", "line 4: unknown structure 'octree'");
    refuses(head + "prefer bvh-sah 1.5\n", "line 4: expected 'prefer STRUCTURE SHARE' with 0 <= SHARE < 1");
    refuses(head + "prefer bvh-sah\n", "line 4: expected 'prefer STRUCTURE SHARE'");
    CHECK_NOTHROW((void)accel::AutoModel::parse(flat_model(100, 100, 0.2)));
}

TEST_CASE("auto: the decision is deterministic and names the model's prediction and margin") {
    const auto scene = perf::replicated(20000);
    const auto view = scene.scene.mesh.view();
    const auto rays = testing::camera_rays(scene.scene.mesh.bounds, 64, 32);
    for (const double budget : {1e3, 1e6, 1e9}) {
        accel::AutoJob job = accel::trace_job(view, rays, budget, accel::Query::closest);
        job.allow_probe = false;
        const auto a = accel::pick_accel(accel::AccelKind::automatic, job);
        const auto b = accel::pick_accel(accel::AccelKind::automatic, job);
        CAPTURE(a.reason);
        CHECK(a.kind == b.kind);
        CHECK(a.path == b.path);
        // Equal up to auto's own time, the last item.
        CHECK(a.reason.substr(0, a.reason.rfind("; auto ")) == b.reason.substr(0, b.reason.rfind("; auto ")));
        CHECK(a.kind != accel::AccelKind::automatic);
        CHECK((a.path == accel::TracePath::packet || a.path == accel::TracePath::single));
        CHECK(a.reason.rfind(std::string(accel::to_string(a.kind)) + ": " + std::string(accel::to_string(a.path)) + " path, model: predicted ", 0) == 0);
        CHECK(a.reason.find("margin") != std::string::npos);
        CHECK(a.reason.find('\n') == std::string::npos);
        CHECK_FALSE(a.probed);
        CHECK_FALSE(a.built);
        REQUIRE_FALSE(a.candidates.empty());
        CHECK(std::is_sorted(a.candidates.begin(), a.candidates.end(),
                             [](const auto& x, const auto& y) { return x.total_ms < y.total_ms; }));
        // The pick is the best prediction, or the preferred structure's best within the model's share.
        const accel::AutoModel& m = accel::builtin_auto_model();
        CHECK((a.candidates.front().kind == a.kind ||
               (a.kind == m.preferred() && a.reason.find(" preferred within ") != std::string::npos)));
        for (const auto& c : a.candidates) CHECK(c.total_ms == doctest::Approx(c.build_ms + c.trace_ms));
    }
    // A named structure is taken as it is, with no reason.
    const auto named = accel::pick_accel(accel::AccelKind::lbvh, accel::trace_job(view, rays, 1e6, accel::Query::closest));
    CHECK(named.kind == accel::AccelKind::lbvh);
    CHECK(named.reason.empty());
}

TEST_CASE("auto: the model's decision prefers the default structure within the model's share") {
    const auto scene = perf::replicated(20000);
    const auto view = scene.scene.mesh.view();
    const auto rays = testing::camera_rays(scene.scene.mesh.bounds, 64, 32);
    // lbvh predicted 4% faster than bvh-sah on both paths (equal builds): the model alone decides.
    auto decide = [&](const std::string& prefer_line) {
        const auto model = accel::AutoModel::parse(flat_model(100, 104, 0.5) + prefer_line);
        accel::AutoJob job = accel::trace_job(view, rays, 1e6, accel::Query::closest);
        job.model = &model;
        job.allow_probe = false;
        return accel::pick_accel(accel::AccelKind::automatic, job);
    };
    const auto within = decide("prefer bvh-sah 0.05\n");
    CAPTURE(within.reason);
    CHECK(within.kind == accel::AccelKind::bvh_sah);
    CHECK(within.reason.find(" preferred within 5% of the best prediction; next lbvh/") != std::string::npos);
    CHECK(within.reason.find(", -3% (within the model's 50% margin)") != std::string::npos);  // (builds counted)
    CHECK(within.candidates.front().kind == accel::AccelKind::lbvh);  // still smallest total first
    const auto outside = decide("prefer bvh-sah 0.03\n");
    CAPTURE(outside.reason);
    CHECK(outside.kind == accel::AccelKind::lbvh);
    CHECK(outside.reason.find("preferred") == std::string::npos);
    CHECK(decide("").kind == accel::AccelKind::lbvh);
    // Never beyond the margin: a share above it counts as the margin.
    const auto model = accel::AutoModel::parse(flat_model(100, 130, 0.2) + "prefer bvh-sah 0.5\n");
    accel::AutoJob job = accel::trace_job(view, rays, 1e6, accel::Query::closest);
    job.model = &model;
    job.allow_probe = false;
    CHECK(accel::pick_accel(accel::AccelKind::automatic, job).kind == accel::AccelKind::lbvh);
}

TEST_CASE("auto: a tiny job takes no probe, whatever the model's doubt") {
    const auto scene = perf::replicated(20000);
    const auto view = scene.scene.mesh.view();
    const auto rays = testing::random_rays_into(scene.scene.mesh.bounds, 1000, 5);
    // The two structures predicted equal: contenders, but 1000 rays cannot pay for a probe.
    const auto model = accel::AutoModel::parse(flat_model(200, 200, 0.5));
    accel::AutoJob job = accel::trace_job(view, rays, 1000.0, accel::Query::closest);
    job.model = &model;
    const auto p = accel::pick_accel(accel::AccelKind::automatic, job);
    CAPTURE(p.reason);
    CHECK_FALSE(p.probed);
    CHECK_FALSE(p.built);
    CHECK(p.reason.find("(within the model's 50% margin), no probe: it would cost") != std::string::npos);
    // With the built-in model too: the 1000-ray job of the issue is decided by the model alone.
    const auto q = accel::pick_accel(accel::AccelKind::automatic, accel::trace_job(view, rays, 1000.0, accel::Query::closest));
    CAPTURE(q.reason);
    CHECK_FALSE(q.probed);
    CHECK(q.reason.find(" model: predicted ") != std::string::npos);
}

TEST_CASE("auto: two paths of one structure are probed only when their traces are worth the probe") {
    const engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 3, 0.2f, 3);
    const auto rays = testing::random_rays_into(mesh.bounds, 1000, 7);
    // lbvh's two paths predicted equal (contenders), bvh-sah 10x slower; every build 1 s, so 2% of
    // the job would pay for timing 1,000 rays, but the paths' 0.2 ms of tracing cannot.
    const std::string model_text = "arbor-auto-model 1\nsource test\ntrace_features one\nbuild_features one\nmargin 0.5\n"
                                   "build lbvh " + std::to_string(std::log(1000.0)) + "\nbuild bvh-sah " +
                                   std::to_string(std::log(1000.0)) + "\ntrace lbvh packet " + std::to_string(std::log(200.0)) +
                                   "\ntrace lbvh single " + std::to_string(std::log(200.0)) + "\ntrace bvh-sah packet " +
                                   std::to_string(std::log(2000.0)) + "\ntrace bvh-sah single " + std::to_string(std::log(2000.0)) + "\n";
    const auto model = accel::AutoModel::parse(model_text);
    accel::AutoJob job = accel::trace_job(mesh.view(), rays, 1000.0, accel::Query::closest);
    job.model = &model;
    const auto p = accel::pick_accel(accel::AccelKind::automatic, job);
    CAPTURE(p.reason);
    CHECK_FALSE(p.probed);
    CHECK(p.kind == accel::AccelKind::lbvh);
    CHECK(p.reason.find("no probe: it would cost") != std::string::npos);
    CHECK(p.reason.find("of what it can win") != std::string::npos);
    CHECK(p.reason.find("the margin x the trace") != std::string::npos);
    // The same rays standing for 1e8 rays: 20 s of tracing, worth a probe of both paths.
    job.groups.front().shape.rays = 1e8;
    const auto q = accel::pick_accel(accel::AccelKind::automatic, job);
    CAPTURE(q.reason);
    CHECK(q.probed);
    CHECK(q.kind == accel::AccelKind::lbvh);
}

TEST_CASE("auto: a large job the model cannot decide is probed, and the probe's pick is handed over") {
    const engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 4, 0.2f, 3);
    const auto view = mesh.view();
    const auto rays = testing::random_rays_into(mesh.bounds, 3000, 9);
    const auto model = accel::AutoModel::parse(flat_model(200, 200, 0.5));
    accel::AutoJob job = accel::trace_job(view, rays, 1e9, accel::Query::closest);
    job.model = &model;
    auto p = accel::pick_accel(accel::AccelKind::automatic, job);
    CAPTURE(p.reason);
    CHECK(p.probed);
    CHECK(p.reason.find(" path, probe: ") != std::string::npos);
    CHECK(p.reason.find("3000 rays timed") != std::string::npos);
    CHECK(p.reason.find("the model had ") != std::string::npos);
    REQUIRE(p.built);
    CHECK(p.built->kind() == p.kind);
    // Four configurations were probed (two structures x two paths), their totals measured.
    std::size_t probed = 0;
    for (const auto& c : p.candidates) probed += c.probed;
    CHECK(probed == 4);
    CHECK(p.candidates.front().probed);
    CHECK(p.candidates.front().kind == p.kind);
    accel::BruteAccel brute(view);
    std::vector<accel::Hit> a(rays.size()), b(rays.size());
    p.built->trace(rays, a, {accel::Query::closest, p.path});
    brute.trace(rays, b, {accel::Query::closest, accel::TracePath::scalar});
    CHECK(testing::count_disagreements(a, b) == 0);
    // Outside the margin (bvh-sah's packets predicted 4x faster than anything else), the same job
    // is the model's alone.
    const auto clear = accel::AutoModel::parse(flat_model(800, 200, 0.5, 800));
    job.model = &clear;
    const auto q = accel::pick_accel(accel::AccelKind::automatic, job);
    CAPTURE(q.reason);
    CHECK_FALSE(q.probed);
    CHECK(q.kind == accel::AccelKind::bvh_sah);
    CHECK(q.path == accel::TracePath::packet);
    CHECK(q.reason.find("outside the model's 50% margin") != std::string::npos);
    // And no probe when it is not allowed.
    job.model = &model;
    job.allow_probe = false;
    CHECK_FALSE(accel::pick_accel(accel::AccelKind::automatic, job).probed);
}

TEST_CASE("auto: a probe times both paths of each structure it builds, whatever the model says of packets") {
    const engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 4, 0.2f, 3);
    const auto view = mesh.view();
    const auto rays = testing::random_rays_into(mesh.bounds, 3000, 11);
    // Packets of lbvh and bvh-sah predicted equal (contenders), single rays 4x slower than packets
    // (outside the 50% margin): the probe still times the single rays of both structures, and on
    // these random rays it is their measured times that decide.
    const auto packets_ahead = accel::AutoModel::parse(flat_model(200, 200, 0.5, 800, 800));
    accel::AutoJob job = accel::trace_job(view, rays, 1e9, accel::Query::closest);
    job.model = &packets_ahead;
    const auto p = accel::pick_accel(accel::AccelKind::automatic, job);
    CAPTURE(p.reason);
    REQUIRE(p.probed);
    std::size_t probed = 0, singles = 0;
    for (const auto& c : p.candidates) {
        probed += c.probed;
        singles += c.probed && c.path == accel::TracePath::single;
    }
    CHECK(probed == 4);
    CHECK(singles == 2);
    CHECK(p.reason.find("/single") != std::string::npos);
    // The pick is the smallest measured total of the four.
    CHECK(p.candidates.front().probed);
    CHECK(p.candidates.front().kind == p.kind);
    CHECK(p.candidates.front().path == p.path);
}

TEST_CASE("auto: a scalar-only build is decided on the scalar path") {
    const engine::Mesh mesh = engine::make_box({0, 0, 0}, {1, 1, 1});
    accel::BuildConfig cfg;
    cfg.layouts = accel::Layouts::scalar;
    const auto rays = accel::rays_into_bounds(mesh.bounds, 64, 9);
    const auto p = accel::pick_accel(accel::AccelKind::automatic,
                                     accel::trace_job(mesh.view(), rays, 1e6, accel::Query::any, accel::TracePath::scalar, cfg));
    CAPTURE(p.reason);
    for (const auto& c : p.candidates) CHECK(c.path == accel::TracePath::best);  // the group's path is fixed
    CHECK(p.path == accel::TracePath::best);
    for (const auto& r : rays) CHECK(accel::BruteAccel(mesh.view()).trace_one(r, accel::Query::closest).is_hit());
}

TEST_CASE("auto: the path policy's expected offer is what each structure offers once built") {
    const engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 2, 0.1f, 3);
    for (const auto layouts : {accel::Layouts::all, accel::Layouts::scalar, accel::Layouts::simd})
        for (const auto k : {accel::AccelKind::brute, accel::AccelKind::bvh_median, accel::AccelKind::bvh_sah,
                             accel::AccelKind::lbvh, accel::AccelKind::kdtree}) {
            accel::BuildConfig cfg;
            cfg.layouts = layouts;
            const auto built = accel::make_accel(k, mesh.view(), cfg);
            const accel::PathOffer want = built->offer(), got = accel::expected_offer(k, cfg);
            INFO(accel::to_string(k), " layouts ", int(layouts));
            for (unsigned p = 0; p < accel::trace_path_count; ++p) CHECK(got.queries[p] == want.queries[p]);
            CHECK(got.packets_pay == want.packets_pay);
            CHECK(got.simd_skipped == want.simd_skipped);
            CHECK(got.counts == want.counts);
        }
}

TEST_CASE("auto: render and converge describe the same rays the same way, so they decide alike") {
    const engine::Scene scene = engine::make_default_scene();
    const engine::LightSet lights(scene);
    engine::RenderSettings set;
    set.width = 64, set.height = 48, set.spp = 6;
    set.integrator = engine::IntegratorKind::path;
    const engine::RenderPlan plan = engine::make_plan(scene, lights, set);
    engine::RenderSettings one = set;
    one.spp = 1;
    const engine::RenderRays a = engine::render_rays(scene, plan, set);
    const engine::RenderRays b = engine::render_rays(scene, engine::make_plan(scene, lights, one), one, 6.0);
    REQUIRE(a.groups.size() == b.groups.size());
    CHECK(a.groups.size() >= 3);  // camera, shadow, bounce
    CHECK(a.groups.front().shape.rays == doctest::Approx(64.0 * 48.0 * 6.0));
    CHECK(a.groups.front().sample.size() == 12 * 16 * 16);  // 12 whole tiles of 16x16 at 64x48
    for (std::size_t g = 0; g < a.groups.size(); ++g) {
        CHECK(a.groups[g].shape.rays == doctest::Approx(b.groups[g].shape.rays));
        CHECK(a.groups[g].shape.query == b.groups[g].shape.query);
        CHECK(a.groups[g].shape.hint == b.groups[g].shape.hint);
    }
    accel::BuildConfig build;
    build.layouts = accel::Layouts::simd;
    accel::AutoJob ja = engine::render_job(scene, a, build), jb = engine::render_job(scene, b, build);
    ja.allow_probe = jb.allow_probe = false;
    const auto pa = accel::pick_accel(accel::AccelKind::automatic, ja), pb = accel::pick_accel(accel::AccelKind::automatic, jb);
    CHECK(pa.kind == pb.kind);
    CHECK(pa.reason.substr(0, pa.reason.rfind("; auto ")) == pb.reason.substr(0, pb.reason.rfind("; auto ")));
    CHECK(pa.path == accel::TracePath::best);  // the renderer's hints choose the paths
    // No light, no shadow group: the plan's skips reach auto.
    engine::Scene dark = scene;
    dark.lights.clear();
    const engine::LightSet none(dark);
    const engine::RenderRays d = engine::render_rays(dark, engine::make_plan(dark, none, set), set);
    for (const auto& g : d.groups) CHECK(g.name != "shadow");
}

TEST_CASE("auto: under max_memory, structures refused before their build starts are left out, and nothing is probed") {
    const engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 4, 0.2f, 3);
    const auto view = mesh.view();
    const auto rays = testing::random_rays_into(mesh.bounds, 3000, 9);
    // lbvh predicted 4x faster: the model's pick without a limit.
    const auto fast_lbvh = accel::AutoModel::parse(flat_model(50, 200, 0.5, 200, 50));
    accel::AutoJob job = accel::trace_job(view, rays, 1e9, accel::Query::closest);
    job.model = &fast_lbvh;
    CHECK(accel::pick_accel(accel::AccelKind::automatic, job).kind == accel::AccelKind::lbvh);
    // A byte under the lbvh's start check: bvh-sah, saying what was left out; and it builds there.
    const std::uint64_t lbvh_start = accel::build_start_bytes(accel::AccelKind::lbvh, mesh.triangle_count(), {});
    REQUIRE(accel::build_start_bytes(accel::AccelKind::bvh_sah, mesh.triangle_count(), {}) < lbvh_start);
    job.build.max_memory = lbvh_start - 1;
    const auto p = accel::pick_accel(accel::AccelKind::automatic, job);
    CAPTURE(p.reason);
    CHECK(p.kind == accel::AccelKind::bvh_sah);
    CHECK(p.reason.find("left out under max_memory, needing more before their build starts: lbvh ") != std::string::npos);
    CHECK(std::none_of(p.candidates.begin(), p.candidates.end(), [](const accel::AutoCandidate& c) { return c.kind == accel::AccelKind::lbvh; }));
    CHECK(accel::make_accel(p.kind, view, job.build)->stats().build_peak_bytes <= job.build.max_memory);
    // A job the model cannot decide is not probed under a limit (the probe holds its builds at once).
    const auto even = accel::AutoModel::parse(flat_model(200, 200, 0.5));
    job.model = &even;
    job.build.max_memory = 1ull << 30;
    const auto q = accel::pick_accel(accel::AccelKind::automatic, job);
    CAPTURE(q.reason);
    CHECK_FALSE(q.probed);
    CHECK(q.reason.find("no probe under max_memory") != std::string::npos);
    CHECK(q.reason.find("left out") == std::string::npos);
    // When every structure would be refused, none is left out: the pick's build says why.
    job.model = &fast_lbvh;
    job.build.max_memory = 1000;
    const auto r = accel::pick_accel(accel::AccelKind::automatic, job);
    CHECK(r.kind == accel::AccelKind::lbvh);
    CHECK(r.reason.find("left out") == std::string::npos);
    CHECK_THROWS_AS((void)accel::make_accel(r.kind, view, job.build), accel::MemoryLimitError);
}
