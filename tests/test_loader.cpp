// OBJ loading: the bad-input table of shared/scenes/bad/README.md, triangle numbering of
// spec/rayfile.md (file order, fan triangulation), relative indices, and the real models.
#include "engine/error.h"
#include "engine/obj_loader.h"
#include "testing.h"

#include <doctest/doctest.h>

#include <filesystem>
#include <map>

using namespace arbor;

namespace {

enum class Expect { error, loads, loads_with_warning };
struct BadCase {
    Expect expect;
    const char* message;  ///< part of the error text (after "FILE:LINE: " when line > 0)
    int line;             ///< the line the error must name; 0: none required
};

// The behaviour each file must get, from shared/scenes/bad/README.md.
const std::map<std::string, BadCase> bad_table = {
    {"nan_vertex.obj", {Expect::error, "not finite", 3}},
    {"inf_vertex.obj", {Expect::error, "not finite", 2}},
    {"index_out_of_range.obj", {Expect::error, "out of range", 4}},
    {"zero_index.obj", {Expect::error, "index 0", 4}},
    {"negative_index_out_of_range.obj", {Expect::error, "out of range", 4}},
    {"empty.obj", {Expect::error, "no triangles", 0}},
    {"no_triangles.obj", {Expect::error, "no triangles", 0}},
    {"truncated.obj", {Expect::error, "no triangles", 0}},
    {"huge_coordinates.obj", {Expect::loads, "", 0}},
    {"all_degenerate.obj", {Expect::loads, "", 0}},
    {"binary_garbage.obj", {Expect::error, "", 0}},
    {"missing_mtl.obj", {Expect::loads_with_warning, "material library", 0}},
    {"mixed_bad_face_tokens.obj", {Expect::error, "malformed face token '1//x'", 7}},
};

engine::Mesh load_text(const std::string& text, engine::Warnings& w) {
    return engine::load_obj_text(text, "test.obj", "", w);
}

}  // namespace

TEST_CASE("loader: every file of shared/scenes/bad behaves as its README table says") {
    const std::string dir = testing::shared_scenes_dir();
    std::size_t seen = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir + "/bad")) {
        if (entry.path().extension() != ".obj") continue;
        const std::string name = entry.path().filename().string();
        CAPTURE(name);
        const auto it = bad_table.find(name);
        REQUIRE_MESSAGE(it != bad_table.end(), "a bad file without an expected behaviour");
        ++seen;
        const BadCase& c = it->second;
        engine::Warnings w;
        if (c.expect == Expect::error) {
            try {
                (void)engine::load_obj(entry.path().string(), w);
                FAIL("loaded without an error");
            } catch (const engine::InputError& e) {
                const std::string msg = e.what();
                CAPTURE(msg);
                const std::string prefix = entry.path().string() + (c.line ? ":" + std::to_string(c.line) + ":" : ":");
                CHECK(msg.rfind(prefix, 0) == 0);
                CHECK(msg.find(c.message) != std::string::npos);
                CHECK(msg.find('\n') == std::string::npos);
            }
        } else {
            const engine::Mesh m = engine::load_obj(entry.path().string(), w);
            CHECK(m.triangle_count() > 0);
            if (c.expect == Expect::loads_with_warning) {
                REQUIRE(w.lines.size() == 1);
                CHECK(w.lines[0].find(c.message) != std::string::npos);
            } else {
                CHECK(w.lines.empty());
            }
        }
    }
    CHECK(seen == bad_table.size());
}

TEST_CASE("loader: polygons are fanned in file order as rayfile.md numbers them") {
    engine::Warnings w;
    const auto m = load_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
                             "f 1 2 3 4 5\nf 5 4 3\n",
                             w);
    REQUIRE(m.triangle_count() == 4);
    const std::vector<std::uint32_t> expected = {0, 1, 2, 0, 2, 3, 0, 3, 4, 4, 3, 2};
    CHECK(m.indices == expected);
}

TEST_CASE("loader: negative indices are relative to the vertices read so far") {
    engine::Warnings w;
    const auto m = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 5 5\nf -4 -1 -2\n", w);
    const std::vector<std::uint32_t> expected = {0, 1, 2, 0, 3, 2};
    CHECK(m.indices == expected);
}

TEST_CASE("loader: face tokens with texture and normal indices") {
    engine::Warnings w;
    const auto m = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2//1 3/1\n", w);
    CHECK(m.triangle_count() == 1);
}

TEST_CASE("loader: errors name the line") {
    engine::Warnings w;
    auto error_of = [&](const std::string& text) -> std::string {
        try {
            (void)load_text(text, w);
        } catch (const engine::InputError& e) {
            return e.what();
        }
        return "loaded";
    };
    CHECK(error_of("v 0 0 0\nv 1 0 0\nv 0 1 x\nf 1 2 3\n") == "test.obj:3: malformed vertex coordinate 'x'");
    CHECK(error_of("v 0 0 0\nv 1 0 0\nv 0 1\nf 1 2 3\n") == "test.obj:3: vertex needs 3 coordinates");
    CHECK(error_of("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\n\r\nf 1 2 4\r\n").rfind("test.obj:5: face index 4 is out of range", 0) == 0);
    CHECK(error_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3/\n") == "test.obj:4: malformed face token '3/'");
    CHECK(error_of("v 1e39 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").rfind("test.obj:1:", 0) == 0);
    CHECK(error_of("# nothing\n") == "test.obj: no triangles");
    // A malformed last line without a line break is a cut-off file: ignored with a warning.
    w.lines.clear();
    CHECK(load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2/", w).triangle_count() == 1);
    REQUIRE(w.lines.size() == 1);
    CHECK(w.lines[0] == "test.obj:5: incomplete last line ignored (malformed face token '2/')");
}

TEST_CASE("loader: a face with fewer than 3 vertices gets no number and a warning") {
    engine::Warnings w;
    const auto m = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\nf 1 2 3\n", w);
    CHECK(m.triangle_count() == 1);
    REQUIRE(w.lines.size() == 1);
    CHECK(w.lines[0] == "test.obj:4: face with fewer than 3 vertices skipped");
}

TEST_CASE("loader: the shared models load with the triangle counts of their README") {
    const std::map<std::string, std::size_t> counts = {
        {"stanford-bunny.obj", 69451}, {"beast.obj", 64618}, {"rocker-arm.obj", 20088}, {"cheburashka.obj", 13334},
        {"teapot.obj", 6320},          {"spot.obj", 5856},   {"cow.obj", 5804},         {"alligator.obj", 5981},
        {"woody.obj", 1267},           {"suzanne.obj", 968},
    };
    for (const auto& path : testing::model_paths()) {
        const std::string name = std::filesystem::path(path).filename().string();
        CAPTURE(name);
        engine::Warnings w;
        const engine::Mesh m = engine::load_obj(path, w);
        REQUIRE(counts.count(name));
        CHECK(m.triangle_count() == counts.at(name));
        CHECK_FALSE(m.bounds.empty());
    }
}
