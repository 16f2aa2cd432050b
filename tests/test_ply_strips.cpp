// PLY `tristrips`: strips cut into triangles with the winding alternating, degenerate joints
// dropped, -1 restarting a strip. The expected triangles are written out by hand here, and the
// regression files (tests/data/meshes/strips-*.ply: three ribbons in z = 0) are also checked
// geometrically: every triangle of a correctly wound ribbon faces -z.
#include "engine/error.h"
#include "engine/formats/tristrip.h"
#include "engine/mesh_loader.h"

#include <doctest/doctest.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

using namespace arbor;
using Tri = std::array<std::int64_t, 3>;

namespace {

std::vector<Tri> strip(const std::vector<std::int64_t>& indices, engine::formats::StripCounts* counts = nullptr) {
    std::vector<Tri> out;
    const auto c = engine::formats::strip_triangles(indices, out);
    if (counts) *counts = c;
    return out;
}

std::vector<Tri> triangles_of(const engine::Mesh& m) {
    std::vector<Tri> out;
    for (std::size_t t = 0; t < m.triangle_count(); ++t)
        out.push_back({m.indices[3 * t], m.indices[3 * t + 1], m.indices[3 * t + 2]});
    return out;
}

const std::string data_dir = std::string(ARBOR_SOURCE_DIR) + "/tests/data/meshes/";

}  // namespace

TEST_CASE("ply strips: windows alternate their winding, joints are dropped, -1 restarts") {
    CHECK(strip({0, 1, 2, 3, 4}) == std::vector<Tri>{{0, 1, 2}, {2, 1, 3}, {2, 3, 4}});
    CHECK(strip({0, 1}).empty());
    CHECK(strip({}).empty());
    CHECK(strip({-1, -1, 5, 6, 7, -1}) == std::vector<Tri>{{5, 6, 7}});
    // The restart resets the parity: 7 8 9 starts even again although it is window 3 of the list.
    CHECK(strip({0, 1, 2, -1, 7, 8, 9, 10}) == std::vector<Tri>{{0, 1, 2}, {7, 8, 9}, {9, 8, 10}});
    // A joint of two repeated indices: four windows dropped, and the parity runs on over them.
    engine::formats::StripCounts c;
    CHECK(strip({0, 1, 2, 3, 3, 4, 4, 5, 6}, &c) == std::vector<Tri>{{0, 1, 2}, {2, 1, 3}, {4, 5, 6}});
    CHECK(c.triangles == 3);
    CHECK(c.degenerate == 4);
    // An odd joint (one repeated index) flips the next strip, as its writer meant.
    CHECK(strip({0, 1, 2, 2, 3, 4}) == std::vector<Tri>{{0, 1, 2}, {3, 2, 4}});
}

TEST_CASE("ply strips: the regression files, ASCII and binary little-endian, triangle by triangle") {
    // Record 1: ribbon A (0-5), a joint 5 5 6 6, ribbon B (6-9). Record 2: a strip of two indices
    // (nothing), -1, ribbon C (10-13), -1.
    const std::vector<Tri> want = {{0, 1, 2}, {2, 1, 3}, {2, 3, 4},    {4, 3, 5},
                                   {6, 7, 8}, {8, 7, 9}, {10, 11, 12}, {12, 11, 13}};
    for (const char* file : {"strips-ascii.ply", "strips-le.ply"}) {
        CAPTURE(file);
        engine::Warnings w;
        const engine::Mesh m = engine::load_mesh(data_dir + file, w);
        CHECK(triangles_of(m) == want);
        CHECK(w.lines.empty());
        const auto v = m.view();
        for (std::size_t t = 0; t < m.triangle_count(); ++t) {
            const auto n = simd::cross(v.corner(t, 1) - v.corner(t, 0), v.corner(t, 2) - v.corner(t, 0));
            CHECK(n.z < 0.0f);
        }
    }
}

TEST_CASE("ply strips: numbered in element order with faces, bad strip indices name the record") {
    const std::string head =
        "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string verts = "0 0 0\n1 0 0\n0 1 0\n1 1 0\n2 0 0\n";
    engine::Warnings w;
    const engine::Mesh m =
        engine::load_mesh_bytes(head +
                                    "element tristrips 1\nproperty list uchar int vertex_indices\n"
                                    "element face 1\nproperty list uchar int vertex_indices\nend_header\n" +
                                    verts + "4 0 1 2 3\n3 1 4 3\n",
                                "mixed.ply", "", w);
    CHECK(triangles_of(m) == std::vector<Tri>{{0, 1, 2}, {2, 1, 3}, {1, 4, 3}});
    const std::string strips = "element tristrips 1\nproperty list uchar int vertex_indices\nend_header\n" + verts;
    CHECK_THROWS_WITH_AS(engine::load_mesh_bytes(head + strips + "4 0 1 2 5\n", "past.ply", "", w),
                         "past.ply: tristrips record 1 refers to vertex 5, past the 5 vertices of its mesh",
                         engine::InputError);
    CHECK_THROWS_WITH_AS(engine::load_mesh_bytes(head + strips + "4 0 1 -2 3\n", "neg.ply", "", w),
                         "neg.ply: tristrips record 1 has the negative vertex index -2", engine::InputError);
    // Strips that are all joints give no triangle, and say so without claiming points or lines.
    CHECK_THROWS_WITH_AS(engine::load_mesh_bytes(head + strips + "4 0 0 1 1\n", "joints.ply", "", w),
                         "joints.ply: no triangles", engine::InputError);
}
