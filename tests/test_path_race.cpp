// The race of the two SIMD paths (accel/interface/path_race.h): which batches are raced, which
// chunks run on which path, the winner by CPU time, and that a raced batch answers as each path
// alone does, bit for bit, on 1 and 2 threads.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <atomic>
#include <cstring>
#include <ctime>
#include <set>
#include <vector>

#include "accel/factory/make_accel.h"
#include "accel/interface/path_race.h"
#include "accel/interface/trace.h"
#include "arbor/arbor.h"
#include "engine/ray_gen.h"
#include "testing.h"

namespace accel = arbor::accel;
namespace engine = arbor::engine;
namespace testing = arbor::testing;
using accel::Hit;
using accel::Ray;
using accel::TracePath;

namespace {

bool same_bits(const Hit& a, const Hit& b) { return std::memcmp(&a, &b, sizeof(Hit)) == 0; }

/// Burns `ns` nanoseconds of this thread's CPU time.
void spin_cpu(std::uint64_t ns) {
    timespec t0{}, t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
    do clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    while (std::uint64_t(t.tv_sec - t0.tv_sec) * 1000000000u + std::uint64_t(t.tv_nsec) - std::uint64_t(t0.tv_nsec) <
           ns);
}

/// Races `chunks` fake chunks of 1024 rays, `slow` burning 300 ns of CPU per ray and the other
/// none; checks that every ray ran exactly once, each race chunk's halves on the paths race_chunks
/// names (even blocks: single for even i, packet for odd i), every other chunk whole on the
/// winner, and that the winner is the other path.
void check_fake_race(std::size_t chunks, TracePath slow) {
    const std::size_t count = accel::race_chunk_count(chunks);
    REQUIRE(count > 0);
    constexpr std::size_t n = 1024;
    std::vector<std::atomic<int>> runs(chunks * n);
    std::vector<TracePath> path_of(chunks * n, TracePath::best);
    std::vector<std::atomic<int>> whole(chunks);
    const accel::RaceOutcome out =
        accel::race_chunks(chunks, count, [&](std::size_t k, TracePath p, accel::ChunkPart part) {
            std::size_t traced = 0;
            for (std::size_t i = 0; i < n; ++i)
                if (accel::in_part(i, part)) ++runs[k * n + i], path_of[k * n + i] = p, ++traced;
            if (part == accel::ChunkPart::all) ++whole[k];
            if (p == slow) spin_cpu(300 * traced);
            return traced;
        });
    const TracePath fast = slow == TracePath::packet ? TracePath::single : TracePath::packet;
    CHECK(out.raced());
    CHECK(out.path == fast);
    CHECK(out.chunks == count);
    CHECK((slow == TracePath::packet ? out.packet_ns > out.single_ns : out.single_ns > out.packet_ns));
    const std::vector<std::size_t> ids = accel::race_chunk_ids(chunks, count);
    std::set<std::size_t> race(ids.begin(), ids.end());
    for (std::size_t r = 0; r < ids.size(); ++r) {
        const TracePath even = r % 2 ? TracePath::packet : TracePath::single,
                        odd = r % 2 ? TracePath::single : TracePath::packet;
        CHECK(whole[ids[r]] == 0);
        for (std::size_t i = 0; i < n; ++i)
            CHECK(path_of[ids[r] * n + i] == ((i / accel::race_block) % 2 ? odd : even));
    }
    std::size_t wrong_runs = 0, wrong_path = 0;
    for (std::size_t k = 0; k < chunks; ++k)
        for (std::size_t i = 0; i < n; ++i) {
            wrong_runs += runs[k * n + i] != 1;
            if (!race.count(k)) wrong_path += path_of[k * n + i] != fast;
        }
    CHECK(wrong_runs == 0);
    CHECK(wrong_path == 0);
}

/// Diffuse rays (engine/ray_gen.h: bounces from the primary hits of 8x8 tiles) over the
/// procedural shapes: groups that start together without sharing an octant.
std::vector<Ray> diffuse_rays(const engine::Mesh& mesh, const accel::Accel& tracer, std::size_t n) {
    engine::Scene scene;
    scene.mesh = mesh;
    engine::RayGenConfig cfg;
    cfg.kind = engine::RayKind::diffuse;
    cfg.count = n;
    cfg.seed = 3;
    return engine::generate_rays(engine::ray_gen_scene(scene), cfg, &tracer);
}

}  // namespace

TEST_CASE("path race: sizes, and the race's chunks are distinct and spread over the batch") {
    CHECK(accel::race_chunk_count(0) == 0);
    CHECK(accel::race_chunk_count(31) == 0);
    CHECK(accel::race_chunk_count(32) == 4);
    CHECK(accel::race_chunk_count(127) == 4);
    CHECK(accel::race_chunk_count(128) == 8);
    CHECK(accel::race_chunk_count(100000) == 8);
    for (const std::size_t chunks : {32u, 33u, 100u, 127u, 128u, 129u, 1000u, 65536u}) {
        CAPTURE(chunks);
        const std::size_t count = accel::race_chunk_count(chunks);
        const auto ids = accel::race_chunk_ids(chunks, count);
        REQUIRE(ids.size() == count);
        CHECK(std::set<std::size_t>(ids.begin(), ids.end()).size() == ids.size());
        CHECK(ids.back() < chunks);
        CHECK(ids.back() >= chunks / 2);  // spread, not all at the start
    }
    // Blocks of 64 rays alternate between the halves; `all` holds every ray.
    for (std::size_t i = 0; i < 300; ++i) {
        CHECK(accel::in_part(i, accel::ChunkPart::all));
        CHECK(accel::in_part(i, accel::ChunkPart::even_blocks) != accel::in_part(i, accel::ChunkPart::odd_blocks));
        CHECK(accel::in_part(i, accel::ChunkPart::even_blocks) == ((i / 64) % 2 == 0));
    }
}

TEST_CASE("path race: the path with less CPU time per ray wins, every chunk runs once, 1 and 2 threads") {
    for (const int threads : {1, 2}) {
        CAPTURE(threads);
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        check_fake_race(40, TracePath::packet);
        check_fake_race(40, TracePath::single);
        check_fake_race(300, TracePath::packet);
        check_fake_race(300, TracePath::single);
    }
}

TEST_CASE("path race: only closest-hit batches the measure cannot call are raced") {
    const engine::Mesh mesh = testing::procedural_shapes();
    const auto bvh = accel::make_accel(accel::AccelKind::bvh_sah, mesh.view());
    const accel::PathOffer& offer = bvh->offer();
    const std::vector<Ray> diffuse = diffuse_rays(mesh, *bvh, 64 * 1024);
    const accel::TraceRequest closest{accel::Query::closest};
    const accel::PathChoice c = accel::choose_path(offer, diffuse, closest);
    REQUIRE(c.why == accel::PathChoice::Why::measured);
    CHECK(!c.one_octant);
    CHECK(accel::race_settles(c, offer, closest));
    // Any-hit answers may differ by path in which triangle blocks: never raced.
    const accel::TraceRequest any{accel::Query::any};
    CHECK(!accel::race_settles(accel::choose_path(offer, diffuse, any), offer, any));
    // A hint, a named path, coherent (camera) rays and scattered (random) rays: the policy decides.
    const accel::TraceRequest hinted{accel::Query::closest, TracePath::best, accel::RayHint::incoherent};
    CHECK(!accel::race_settles(accel::choose_path(offer, diffuse, hinted), offer, hinted));
    const accel::TraceRequest named{accel::Query::closest, TracePath::packet};
    CHECK(!accel::race_settles(accel::choose_path(offer, diffuse, named), offer, named));
    const auto camera = testing::camera_rays(mesh.bounds, 256, 256);
    CHECK(!accel::race_settles(accel::choose_path(offer, camera, closest), offer, closest));
    const auto random = testing::random_rays_into(mesh.bounds, 64 * 1024, 5);
    CHECK(!accel::race_settles(accel::choose_path(offer, random, closest), offer, closest));
    // A structure with one path (brute) has nothing to race.
    const auto brute = accel::make_accel(accel::AccelKind::brute, mesh.view());
    CHECK(!accel::race_settles(accel::choose_path(brute->offer(), diffuse, closest), brute->offer(), closest));
    // trace_parallel: a diffuse batch of 64 chunks is raced, one of 31 chunks and an any-hit batch not.
    std::vector<Hit> hits(diffuse.size());
    CHECK(accel::trace_parallel(*bvh, diffuse, hits, accel::Query::closest).raced());
    CHECK(!accel::trace_parallel(*bvh, diffuse, hits, accel::Query::any).raced());
    const std::span<const Ray> small(diffuse.data(), 31 * 1024);
    CHECK(
        !accel::trace_parallel(*bvh, small, std::span<Hit>(hits.data(), small.size()), accel::Query::closest).raced());
}

TEST_CASE(
    "path race: a raced batch answers as each path alone, bit for bit, on 1 and 2 threads (every structure with both "
    "paths)") {
    const engine::Mesh mesh = testing::procedural_shapes();
    for (const auto kind : {accel::AccelKind::bvh_sah, accel::AccelKind::lbvh, accel::AccelKind::kdtree}) {
        CAPTURE(accel::to_string(kind));
        const auto a = accel::make_accel(kind, mesh.view());
        const std::vector<Ray> rays = diffuse_rays(mesh, *a, 128 * 1024);
        std::vector<Hit> single(rays.size()), packet(rays.size());
        accel::trace_parallel(*a, rays, single, accel::Query::closest, TracePath::single);
        accel::trace_parallel(*a, rays, packet, accel::Query::closest, TracePath::packet);
        for (const int threads : {1, 2}) {
            CAPTURE(threads);
            const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
            std::vector<Hit> raced(rays.size());
            const accel::RaceOutcome out = accel::trace_parallel(*a, rays, raced, accel::Query::closest);
            CHECK(out.raced());
            CHECK(out.chunks == 8);
            CHECK(out.single_ns > 0.0);
            CHECK(out.packet_ns > 0.0);
            std::size_t differ_single = 0, differ_packet = 0;
            for (std::size_t i = 0; i < rays.size(); ++i) {
                differ_single += !same_bits(raced[i], single[i]);
                differ_packet += !same_bits(raced[i], packet[i]);
            }
            CHECK(differ_single == 0);
            CHECK(differ_packet == 0);
        }
    }
}

TEST_CASE("path race: the public API's intersect on a raced batch answers as brute force, on 1 and 2 threads") {
    const engine::Mesh mesh = testing::procedural_shapes();
    const auto bvh = accel::make_accel(accel::AccelKind::bvh_sah, mesh.view());
    const std::vector<Ray> rays = diffuse_rays(mesh, *bvh, 40 * 1024);
    REQUIRE(accel::race_settles(accel::choose_path(bvh->offer(), rays, {}), bvh->offer(), {}));
    std::vector<float> pos;
    for (std::size_t i = 0; i < mesh.vertex_count(); ++i) pos.insert(pos.end(), {mesh.x[i], mesh.y[i], mesh.z[i]});
    std::vector<std::uint32_t> idx(mesh.indices.begin(), mesh.indices.end());
    std::vector<arbor::Ray> api_rays(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Ray& r = rays[i];
        api_rays[i] = {{r.org.x, r.org.y, r.org.z}, r.tnear, {r.dir.x, r.dir.y, r.dir.z}, r.tfar};
    }
    const auto run = [&](const char* accel_name, int threads) {
        arbor::Scene scene;
        scene.add_mesh(pos, idx);
        scene.build({accel_name, threads});
        std::vector<arbor::Hit> hits(rays.size());
        scene.intersect(arbor::RayArrays::of(api_rays.data(), api_rays.size()), hits.data());
        return hits;
    };
    const auto ref = run("brute", 2);
    for (const int threads : {1, 2}) {
        CAPTURE(threads);
        const auto got = run("bvh-sah", threads);
        std::size_t differ = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) differ += std::memcmp(&got[i], &ref[i], sizeof(arbor::Hit)) != 0;
        CHECK(differ == 0);
    }
}
