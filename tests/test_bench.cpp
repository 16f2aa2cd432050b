// The benchmark's parts that can be checked without timing: the statistics mode of brute, the
// procedural scenes (exact sizes, finite, deterministic, usable by every ray kind), the scene
// plan, summarize(), and a tiny run of the driver whose reports are complete and consistent.
#include "accel/factory/make_accel.h"
#include "accel/structures/brute_accel.h"
#include "engine/error.h"
#include "engine/ray_gen.h"
#include "perf/bench_build.h"
#include "perf/bench_plan.h"
#include "perf/bench_report.h"
#include "perf/bench_run.h"
#include "perf/bench_wire.h"
#include "perf/scenes.h"
#include "testing.h"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

using namespace arbor;

TEST_CASE("trace counters: brute counts one node and every triangle per traceable ray") {
    const auto s = perf::tiny_scene();
    const auto view = s.scene.mesh.view();
    accel::BruteAccel brute(view);
    auto rays = testing::random_rays_into(s.scene.mesh.bounds, 200, 3);
    rays.push_back({{0, 0, 0}, 0.0f, {0, 0, 0}, INFINITY});  // untraceable: counted as a ray only
    std::vector<accel::Hit> counted(rays.size()), plain(rays.size());
    accel::TraceCounters c;
    REQUIRE(brute.offer().counts);
    brute.trace(rays, counted, {accel::Query::closest, accel::TracePath::scalar, {}, {}, &c});
    brute.trace(rays, plain, {accel::Query::closest, accel::TracePath::scalar});
    CHECK(testing::count_disagreements(counted, plain) == 0);
    CHECK(c.rays == rays.size());
    CHECK(c.nodes_visited == rays.size() - 1);
    CHECK(c.triangles_tested == (rays.size() - 1) * view.triangle_count());
    // Any hit stops at the first hit: fewer tests, never more.
    accel::TraceCounters any;
    brute.trace(rays, counted, {accel::Query::any, accel::TracePath::scalar, {}, {}, &any});
    CHECK(any.triangles_tested < c.triangles_tested);
    CHECK(any.rays == c.rays);
}

TEST_CASE("bench scenes: exact sizes, finite, deterministic, and every ray kind can be made") {
    CHECK(perf::replicated(1000).scene.mesh.triangle_count() == 1000);
    CHECK(perf::replicated(12345).scene.mesh.triangle_count() == 12345);
    CHECK(perf::replicated(1000).name == "replicated-1e3");
    CHECK(perf::grass_field(500).scene.mesh.triangle_count() == 502);
    CHECK(perf::triangle_soup(700).scene.mesh.triangle_count() == 700);
    const auto a = perf::triangle_soup(300, 5), b = perf::triangle_soup(300, 5), c = perf::triangle_soup(300, 6);
    CHECK(a.scene.mesh.x == b.scene.mesh.x);
    CHECK(a.scene.mesh.x != c.scene.mesh.x);

    std::vector<perf::BenchScene> scenes;
    scenes.push_back(perf::tiny_scene());
    scenes.push_back(perf::teapot_in_stadium(nullptr));
    scenes.push_back(perf::architectural_interior(1));
    scenes.push_back(perf::grass_field(2000));
    scenes.push_back(perf::triangle_soup(2000));
    scenes.push_back(perf::replicated(3000));
    for (const auto& s : scenes) {
        const auto& m = s.scene.mesh;
        INFO(s.name);
        REQUIRE(m.triangle_count() > 0);
        for (std::size_t t = 0; t < m.triangle_count(); ++t) REQUIRE(m.view().triangle_is_finite(t));
        REQUIRE_FALSE(m.bounds.empty());
        if (s.use_scene_camera) CHECK(m.bounds.contains({s.scene.camera.eye, s.scene.camera.eye}));
        const auto gen = engine::ray_gen_scene(s.scene, s.use_scene_camera);
        accel::BruteAccel brute(gen.tris);
        for (auto kind : {engine::RayKind::primary, engine::RayKind::shadow, engine::RayKind::diffuse, engine::RayKind::random}) {
            engine::RayGenConfig cfg;
            cfg.kind = kind;
            cfg.count = 200;
            CHECK(engine::generate_rays(gen, cfg, &brute).size() == 200);
        }
    }
    // The dense model of the stadium sits at the origin, size 1, inside a room 2000 across.
    const auto& st = scenes[1].scene.mesh.bounds;
    CHECK(st.extent().x == doctest::Approx(2000.0f));
}

TEST_CASE("bench plan: scene names, optional models, and errors") {
    perf::BenchOptions o;
    o.models_dir = "/nonexistent";
    o.scenes = {"tiny", "scaling", "grass", "tiny", "?teapot"};
    o.scaling_max_exp = 4;
    const auto plan = perf::plan_scenes(o);
    REQUIRE(plan.size() == 4);
    CHECK(plan[0].name == "tiny");
    CHECK(plan[1].name == "replicated-1e3");
    CHECK(plan[2].name == "replicated-1e4");
    CHECK(plan[3].name == "grass");
    o.scenes = {"teapot"};
    CHECK_THROWS_AS(perf::plan_scenes(o), engine::InputError);
    o.scenes = {"replicated-1e9"};
    CHECK_THROWS_AS(perf::plan_scenes(o), engine::InputError);
}

TEST_CASE("bench: builds predicted to take too long are skipped and noted, history grows") {
    const auto s = perf::replicated(10000);
    perf::BenchOptions o;
    o.structures = {"bvh-median", "bvh-sah"};
    o.embree = false;
    o.max_build_seconds = 1.0;
    perf::BuildHistory history{{"bvh-sah", {1000, 1000.0}}};  // 1 s for 1000 triangles: 13 s predicted here
    std::vector<std::string> notes;
    const auto built = perf::build_structures(s.scene.mesh.view(), o, {1}, 1, notes, history);
    REQUIRE(built.size() == 1);
    CHECK(built[0].name == "bvh-median");
    REQUIRE(notes.size() == 1);
    CHECK(notes[0].find("bvh-sah: skipped on 10000 triangles") == 0);
    REQUIRE(history.count("bvh-median") == 1);
    CHECK(history["bvh-median"].first == 10000);
    CHECK(history["bvh-sah"].first == 1000);  // not built: unchanged
}

TEST_CASE("bench: summarize gives median, min, max") {
    const auto s = perf::summarize({5.0, 1.0, 3.0});
    CHECK(s.median == 3.0);
    CHECK(s.min == 1.0);
    CHECK(s.max == 5.0);
    CHECK(perf::summarize({4.0, 1.0, 2.0, 3.0}).median == 2.5);
    CHECK(std::isnan(perf::summarize({}).median));
}

namespace {
/// The tiny scene's triangles, to ask a structure which paths it has.
accel::TriangleView s_view_for_paths() {
    static const perf::BenchScene s = perf::tiny_scene();
    return s.scene.mesh.view();
}
}  // namespace

TEST_CASE("bench: a tiny run validates every row against brute and writes consistent reports") {
    perf::BenchOptions o;
    o.scenes = {"tiny"};
    o.rays = 512;
    o.repeats = 2;
    o.build_repeats = 1;
    o.time_brute = true;
    o.embree_variants = false;
    o.count_sample = 128;
    o.verbose = false;
    const perf::BenchResult r = perf::run_bench(o);
    REQUIRE_FALSE(r.rows.empty());
    std::size_t brute_rows = 0;
    for (const auto& row : r.rows) {
        INFO(row.structure, " ", row.path, " ", row.kind);
        CHECK(row.rays == 512);
        CHECK(row.brute_sample > 0);
        CHECK(row.mrays.min <= row.mrays.median);
        CHECK(row.mrays.median <= row.mrays.max);
        CHECK(row.total_ms.size() == o.budgets.size());
        CHECK(row.err_brute == 0);  // the tiny scene has no stiff rays: every tracer must agree
        if (row.structure == "brute") {
            ++brute_rows;
            CHECK(row.tris_per_ray > 0.0);
            CHECK(row.nodes_per_ray <= 1.0);
        }
    }
    CHECK(brute_rows == 4 * 2 * 1);  // kinds x threads x paths (brute has only scalar)
    // Every path each structure has is timed, and exactly one of them is the one best takes.
    std::map<std::tuple<std::string, std::string, int>, std::pair<int, std::set<std::string>>> per_structure;
    for (const auto& row : r.rows) {
        if (row.embree) {
            CHECK_FALSE(row.best_path);
            continue;
        }
        auto& e = per_structure[{row.structure, row.kind, row.threads}];
        e.first += row.best_path;
        e.second.insert(row.path);
    }
    for (const auto& entry : per_structure) {
        const auto& key = entry.first;  // not a structured binding: clang 14 cannot capture one in INFO
        const auto& e = entry.second;
        INFO(std::get<0>(key), " ", std::get<1>(key));
        CHECK(e.first == 1);
        const auto kind = *accel::parse_accel_kind(std::get<0>(key));
        const auto acc = accel::make_accel(kind, s_view_for_paths());
        for (const auto p : {accel::TracePath::packet, accel::TracePath::single})
            CHECK(e.second.count(std::string(accel::to_string(p))) == (acc->offer().has(p) ? 1u : 0u));
    }
    // auto on every (kind, threads, budget), judged against the best (structure, path) row.
    CHECK(r.autos.size() == 4 * 2 * o.budgets.size());
    for (const auto& a : r.autos) {
        INFO(a.kind, " ", a.budget, " ", a.reason);
        CHECK_FALSE(a.picked_path.empty());
        CHECK(a.regret_without_auto >= -1e-12);  // best_ms is the smallest total of any row
        CHECK(std::isfinite(a.regret));          // auto's pick was one of the timed rows
        CHECK(a.auto_ms > 0.0);
        CHECK(a.best_ms > 0.0);
        CHECK(a.default_ms >= a.best_ms * (1.0 - 1e-12));
        CHECK(a.auto_total_ms > 0.0);
    }
    const auto j = nlohmann::json::parse(perf::to_json(r));
    CHECK(j["rows"].size() == r.rows.size());
    CHECK(j["meta"]["budgets"].size() == 3);
    std::istringstream csv(perf::to_csv(r));
    std::string line;
    std::size_t lines = 0, header_fields = 0;
    while (std::getline(csv, line)) {
        const auto fields = std::size_t(std::count(line.begin(), line.end(), ',')) + 1;
        if (lines++ == 0) header_fields = fields;
        else CHECK(fields == header_fields);
    }
    CHECK(lines == r.rows.size() + 1);
    const std::string md = perf::to_markdown(r);
    CHECK(md.find("## Headline") != std::string::npos);
    CHECK(md.find("| tiny |") != std::string::npos);

    // What `mpirun arbor bench` sends from rank to rank (rows, auto rows, notes; rank 0 writes the
    // run's own meta data): every field back, NaN kept.
    const perf::BenchResult back = perf::from_wire(perf::to_wire(r));
    perf::BenchResult same_meta = r;
    same_meta.rows = back.rows, same_meta.autos = back.autos, same_meta.notes = back.notes;
    CHECK(perf::to_json(same_meta) == perf::to_json(r));
    REQUIRE(back.rows.size() == r.rows.size());
    for (std::size_t i = 0; i < r.rows.size(); ++i) {
        CHECK(std::isnan(back.rows[i].ratio_embree) == std::isnan(r.rows[i].ratio_embree));
        CHECK(back.rows[i].trace_samples == r.rows[i].trace_samples);
    }
    CHECK_THROWS_AS(perf::from_wire("not cbor"), std::runtime_error);
}

TEST_CASE("bench: a scene share runs each scene where it says and the report keeps plan order") {
    perf::BenchOptions o;
    o.scenes = {"replicated-1e3", "tiny"};
    o.kinds = {"primary"};
    o.structures = {"lbvh"};
    o.threads = {1};
    o.rays = 256;
    o.repeats = 1;
    o.build_repeats = 1;
    o.embree = false;
    o.evaluate_auto = false;
    o.verbose = false;
    std::vector<std::size_t> ran;
    // As on rank 0 of two: scene 1 here, scene 0 "elsewhere" (run here too, sent through the wire).
    const perf::SceneShare share = [&](std::size_t count, const std::function<perf::BenchResult(std::size_t)>& job) {
        std::vector<perf::BenchResult> parts(count);
        for (std::size_t i = count; i-- > 0;) {
            ran.push_back(i);
            parts[i] = i == 0 ? perf::from_wire(perf::to_wire(job(i))) : job(i);
        }
        return parts;
    };
    const perf::BenchResult r = perf::run_bench(o, share);
    CHECK(ran == std::vector<std::size_t>{1, 0});
    REQUIRE(r.rows.size() >= 2);
    CHECK(r.rows.front().scene == "replicated-1e3");
    CHECK(r.rows.back().scene == "tiny");
    const perf::BenchResult none = perf::run_bench(o, [](std::size_t, const auto&) { return std::vector<perf::BenchResult>{}; });
    CHECK(none.rows.empty());  // a rank that does not write the report
}
