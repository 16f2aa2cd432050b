// Every input a fuzzer ever failed on (tests/fuzz/regressions) and every seed (tests/fuzz/seeds,
// shared/scenes/bad), replayed through exactly the code the libFuzzer harnesses run (fuzz/).
#include "fuzz/fuzz_targets.h"
#include "engine/procedural.h"
#include "testing.h"
#include "accel/factory/make_accel.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

std::vector<std::string> files_in(const std::string& dir) {
    std::vector<std::string> out;
    if (std::filesystem::is_directory(dir))
        for (const auto& e : std::filesystem::directory_iterator(dir))
            if (e.is_regular_file()) out.push_back(e.path().string());
    std::sort(out.begin(), out.end());
    return out;
}

std::string bytes_of(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

void replay(const std::vector<std::string>& files, void (*target)(const std::uint8_t*, std::size_t)) {
    for (const auto& path : files) {
        CAPTURE(path);
        const std::string b = bytes_of(path);
        CHECK_NOTHROW(target(reinterpret_cast<const std::uint8_t*>(b.data()), b.size()));
    }
}

const std::string fuzz_dir = std::string(ARBOR_SOURCE_DIR) + "/tests/fuzz";

}  // namespace

TEST_CASE("fuzz regressions: OBJ inputs that once failed, and the seeds, load or fail cleanly") {
    const auto regressions = files_in(fuzz_dir + "/regressions/obj");
    CHECK(!regressions.empty());
    replay(regressions, arbor::fuzz::fuzz_obj);
    replay(files_in(fuzz_dir + "/seeds/obj"), arbor::fuzz::fuzz_obj);
    const std::string shared = arbor::testing::shared_scenes_dir();
    replay(files_in(shared + "/bad"), arbor::fuzz::fuzz_obj);
}

TEST_CASE("fuzz regressions: mesh files of every format (seeds good and broken, regressions) load or fail cleanly") {
    const auto seeds = files_in(fuzz_dir + "/seeds/mesh");
    CHECK(seeds.size() >= 20);
    replay(seeds, arbor::fuzz::fuzz_mesh);
    replay(files_in(fuzz_dir + "/regressions/mesh"), arbor::fuzz::fuzz_mesh);
    const auto data = files_in(std::string(ARBOR_SOURCE_DIR) + "/tests/data/meshes");
    CHECK(!data.empty());
    replay(data, arbor::fuzz::fuzz_mesh);
    replay(files_in(fuzz_dir + "/seeds/obj"), arbor::fuzz::fuzz_mesh);
    const std::string shared = arbor::testing::shared_scenes_dir();
    replay(files_in(shared + "/bad"), arbor::fuzz::fuzz_mesh);
}

TEST_CASE("fuzz regressions: ray and hit files that once failed are read or refused cleanly") {
    const auto regressions = files_in(fuzz_dir + "/regressions/rays");
    CHECK(!regressions.empty());
    replay(regressions, arbor::fuzz::fuzz_rays);
}

TEST_CASE("fuzz regressions: the viewer's message seeds and regressions parse or are refused cleanly") {
    const auto seeds = files_in(fuzz_dir + "/seeds/view");
    CHECK(seeds.size() >= 4);
    replay(seeds, arbor::fuzz::fuzz_view_message);
    replay(files_in(fuzz_dir + "/regressions/view"), arbor::fuzz::fuzz_view_message);
}

namespace {

/// What a broken structure can get wrong, one at a time.
/// (Which triangle a closest hit names is not part of the rayfile.md contract the targets check.)
enum class Break { none, closest_miss, closest_t, any_miss, any_t_out, untraceable_hits };

/// A real bvh-sah that spoils its answers on purpose: the contract check must report each.
class BrokenAccel final : public arbor::accel::Accel {
public:
    BrokenAccel(const arbor::accel::TriangleView& tris, Break b)
        : Accel(arbor::accel::AccelKind::bvh_sah), inner_(arbor::accel::make_accel(kind_, tris)), break_(b) {
        stats_ = inner_->stats();
        offer_ = inner_->offer();
    }

private:
    void run(std::span<const arbor::accel::Ray> rays, std::span<arbor::accel::Hit> hits, arbor::accel::Query query,
             arbor::accel::TracePath path, arbor::accel::TraceCounters*) const override {
        using arbor::accel::Query;
        inner_->trace(rays, hits, {query, path});
        for (std::size_t i = 0; i < rays.size(); ++i) {
            arbor::accel::Hit& h = hits[i];
            if (break_ == Break::untraceable_hits && !arbor::accel::ray_is_traceable(rays[i])) h = {1.0f, 0, 0.0f, 0.0f};
            if (!h.is_hit()) continue;
            if (query == Query::closest && break_ == Break::closest_miss) h = {};
            if (query == Query::closest && break_ == Break::closest_t) h.t *= 1.01f;
            if (query == Query::any && break_ == Break::any_miss) h = {};
            if (query == Query::any && break_ == Break::any_t_out) h.t = rays[i].tnear - 1.0f;
        }
    }

public:  // the list and point queries are not what the ray harness checks: passed through
    void trace_all(std::span<const arbor::accel::Ray> rays, arbor::accel::HitSink& sink) const override {
        inner_->trace_all(rays, sink);
    }
    void closest_points(std::span<const arbor::accel::Vec3f> points, float max_distance,
                        std::span<arbor::accel::PointHit> out) const override {
        inner_->closest_points(points, max_distance, out);
    }

private:
    std::unique_ptr<arbor::accel::Accel> inner_;
    Break break_;
};

}  // namespace

TEST_CASE("fuzz targets: a broken contract is reported, not swallowed") {
    using arbor::fuzz::FuzzFinding;
    CHECK(std::is_base_of_v<std::logic_error, FuzzFinding>);
    // A sound OBJ passes through the target (its structures are checked against brute).
    const std::string quad = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    CHECK_NOTHROW(arbor::fuzz::fuzz_obj(reinterpret_cast<const std::uint8_t*>(quad.data()), quad.size()));
    // The check the targets run, fed structures that break the contract one way each, on rays
    // that hit a small mesh (and one untraceable ray): each is reported as a FuzzFinding.
    const arbor::engine::Mesh mesh = arbor::engine::make_icosphere({0, 0, 0}, 1.0f, 1);
    std::vector<arbor::accel::Ray> rays = arbor::testing::random_rays_into(mesh.bounds, 64, 5);
    rays.push_back({{0, 0, 5}, 0.0f, {0, 0, 0}, INFINITY});  // zero direction: must miss
    CHECK_NOTHROW(arbor::fuzz::check_structure(BrokenAccel(mesh.view(), Break::none), mesh.view(), rays));
    for (const Break b : {Break::closest_miss, Break::closest_t, Break::any_miss, Break::any_t_out, Break::untraceable_hits}) {
        CAPTURE(int(b));
        CHECK_THROWS_AS(arbor::fuzz::check_structure(BrokenAccel(mesh.view(), b), mesh.view(), rays), FuzzFinding);
    }
}
