// PLY, STL and glTF through engine::load_mesh: each format loads files written here
// (perf/mesh_files.h) with the triangles in the order rayfile.md numbers them, the format told by
// the content, polygons triangulated as OBJ's, attributes (normals, colours, texture coordinates,
// node transforms, textures) kept; and the bad-input rows: truncated bodies, counts larger than
// the file, indices past the vertex list, non-finite vertices, files with only points or lines.
#include "engine/error.h"
#include "engine/mesh_loader.h"
#include "engine/procedural.h"
#include "perf/mesh_files.h"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>

using namespace arbor;
using engine::MeshFormat;
using engine::Vec3f;

namespace {

struct Folder {
    std::filesystem::path path;
    Folder() : path(std::filesystem::temp_directory_path() / ("arbor-formats-" + std::to_string(::getpid()))) {
        std::filesystem::create_directories(path);
    }
    ~Folder() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    std::string write(const std::string& name, const std::string& bytes) const {
        std::ofstream(path / name, std::ios::binary) << bytes;
        return (path / name).string();
    }
};

/// A small closed mesh with a vertex shared by many triangles and a size that is not a power of 2.
engine::Mesh sample_mesh() {
    engine::Mesh m = engine::make_icosphere({0.5f, 0.25f, -1.0f}, 1.5f, 1, 0.1f, 7);
    m.compute_bounds();
    return m;
}

/// The corner positions of every triangle, in order: what a reader must reproduce.
std::vector<Vec3f> corners(const engine::Mesh& m) {
    std::vector<Vec3f> out;
    const auto v = m.view();
    for (std::size_t t = 0; t < m.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k) out.push_back(v.corner(t, k));
    return out;
}

bool same(const std::vector<Vec3f>& a, const std::vector<Vec3f>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (!(a[i].x == b[i].x && a[i].y == b[i].y && a[i].z == b[i].z)) return false;
    return true;
}

std::string error_of(const std::string& path) {
    engine::Warnings w;
    try {
        (void)engine::load_mesh(path, w);
    } catch (const engine::InputError& e) {
        return e.what();
    }
    return "loaded";
}

}  // namespace

TEST_CASE("mesh formats: every format gives the same triangles in the same order, told by content") {
    const Folder dir;
    const engine::Mesh m = sample_mesh();
    const auto want = corners(m);
    struct Case {
        std::string file, bytes;
        MeshFormat format;
    };
    perf::GltfOptions gltf_text;
    gltf_text.binary = false;
    std::string bin;
    perf::GltfOptions external = gltf_text;
    external.external_buffer = "buffer.bin";
    const std::string with_bin = perf::gltf_bytes(m, external, &bin);
    dir.write("buffer.bin", bin);
    const std::vector<Case> cases = {
        {"m.obj", perf::obj_text(m), MeshFormat::obj},
        {"a.ply", perf::ply_bytes(m, perf::PlyEncoding::ascii), MeshFormat::ply},
        {"le.ply", perf::ply_bytes(m, perf::PlyEncoding::binary_little_endian), MeshFormat::ply},
        {"be.ply", perf::ply_bytes(m, perf::PlyEncoding::binary_big_endian), MeshFormat::ply},
        {"a.stl", perf::stl_bytes(m, false), MeshFormat::stl_ascii},
        {"b.stl", perf::stl_bytes(m, true), MeshFormat::stl_binary},
        {"m.glb", perf::gltf_bytes(m, {}), MeshFormat::glb},
        {"m.gltf", perf::gltf_bytes(m, gltf_text), MeshFormat::gltf},
        {"external.gltf", with_bin, MeshFormat::gltf},
        // Misnamed files: the content decides.
        {"ply-named.obj", perf::ply_bytes(m, perf::PlyEncoding::binary_little_endian), MeshFormat::ply},
        {"glb-named.stl", perf::gltf_bytes(m, {}), MeshFormat::glb},
        {"stl-named.ply", perf::stl_bytes(m, true), MeshFormat::stl_binary},
        {"no-extension", perf::stl_bytes(m, false), MeshFormat::stl_ascii},
    };
    for (const Case& c : cases) {
        CAPTURE(c.file);
        engine::Warnings w;
        MeshFormat format{};
        const engine::Mesh got = engine::load_mesh(dir.write(c.file, c.bytes), w, 0, &format);
        CHECK(format == c.format);
        CHECK(got.triangle_count() == m.triangle_count());
        CHECK(same(corners(got), want));
        CHECK(w.lines.empty());
    }
}

TEST_CASE("mesh formats: PLY polygons are triangulated as OBJ's, normals and colours kept per vertex") {
    const Folder dir;
    // A quad (fanned: 0 1 2, 0 2 3) and a concave hexagon (an L: ear-clipped into 4 triangles).
    const std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 10\nproperty float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
        "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0 0 0 2 255 0 0\n1 0 0 0 0 1 0 255 0\n1 1 0 0 0 1 0 0 255\n0 1 0 0 0 1 188 188 188\n"
        "3 0 0 0 0 1 0 0 0\n5 0 0 0 0 1 0 0 0\n5 1 0 0 0 1 0 0 0\n4 1 0 0 0 1 0 0 0\n4 2 0 0 0 1 0 0 0\n3 2 0 0 0 1 0 0 0\n"
        "4 0 1 2 3\n6 4 5 6 7 8 9\n";
    engine::Warnings w;
    const engine::Mesh m = engine::load_mesh(dir.write("poly.ply", ply), w);
    REQUIRE(m.triangle_count() == 6);
    CHECK(std::vector<std::uint32_t>(m.indices.begin(), m.indices.begin() + 6) == std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3});
    double area = 0.0;
    const auto v = m.view();
    for (std::size_t t = 2; t < 6; ++t) area += 0.5 * simd::length(simd::cross(v.corner(t, 1) - v.corner(t, 0), v.corner(t, 2) - v.corner(t, 0)));
    CHECK(area == doctest::Approx(3.0));  // the L's area; a fan from its first corner would cover more
    REQUIRE(m.has_normals());
    CHECK(m.normals[0].z == doctest::Approx(1.0f));  // normalised (the file's is 2 long)
    CHECK(m.normal_index[0] == 0);
    REQUIRE(m.colors.size() == 10);
    CHECK(m.colors[0].x == 1.0f);
    CHECK(m.colors[0].y == 0.0f);
    CHECK(m.colors[3].x == doctest::Approx(0.5).epsilon(0.01));  // sRGB code 188 is about linear 0.5
}

TEST_CASE("mesh formats: glTF node transforms, texture coordinates and the base colour texture") {
    const Folder dir;
    engine::Mesh quad;
    quad.add_vertex({0, 0, 0});
    quad.add_vertex({1, 0, 0});
    quad.add_vertex({1, 1, 0});
    quad.add_vertex({0, 1, 0});
    quad.normals = {{0, 0, 1}};
    quad.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    engine::CornerAttributes a;
    a.normal[0] = a.normal[1] = a.normal[2] = 0;
    a.uv[0] = 0, a.uv[1] = 1, a.uv[2] = 2;
    quad.add_triangle(0, 1, 2, 0, a);
    a.uv[0] = 0, a.uv[1] = 2, a.uv[2] = 3;
    quad.add_triangle(0, 2, 3, 0, a);
    quad.compute_bounds();
    perf::GltfOptions o;
    // A 2x4 image: red top half, blue bottom half.
    std::vector<std::uint8_t> rgb;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 2; ++x) rgb.insert(rgb.end(), {std::uint8_t(y < 2 ? 255 : 0), 0, std::uint8_t(y < 2 ? 0 : 255)});
    o.png = perf::png_bytes(2, 4, rgb);
    o.base_color = {0.5f, 1.0f, 1.0f};
    // Rotate 90 degrees about z (x -> y), then move by (10, 0, 0); column-major.
    o.matrix = {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 10, 0, 0, 1};
    engine::Warnings w;
    const engine::Mesh m = engine::load_mesh(dir.write("quad.glb", perf::gltf_bytes(quad, o)), w);
    REQUIRE(m.triangle_count() == 2);
    const Vec3f p1 = m.view().corner(0, 1);  // (1, 0, 0) -> (10, 1, 0)
    CHECK(p1.x == doctest::Approx(10.0f));
    CHECK(p1.y == doctest::Approx(1.0f));
    REQUIRE(m.has_normals());
    CHECK(m.normals[m.normal_index[0]].z == doctest::Approx(1.0f));
    REQUIRE(m.has_uvs());
    // The file stores glTF's v (0 at the image's top); the mesh has OBJ's (0 at the bottom) back.
    CHECK(m.uvs[m.uv_index[2]].u == doctest::Approx(1.0f));
    CHECK(m.uvs[m.uv_index[2]].v == doctest::Approx(1.0f));
    REQUIRE(m.materials.size() == 1);
    CHECK(m.materials[0].diffuse.x == doctest::Approx(0.5f));
    REQUIRE(m.materials[0].diffuse_texture == 0);
    const engine::Texture& t = m.textures[0];
    CHECK(t.width == 2);
    CHECK(t.height == 4);
    CHECK(t.sample(0.5f, 0.8f).x == doctest::Approx(1.0f));  // v near 1: the image's top, red
    CHECK(t.sample(0.5f, 0.2f).z == doctest::Approx(1.0f));  // v near 0: its bottom, blue
    CHECK(w.lines.empty());
}

TEST_CASE("mesh formats: bad inputs give one-line errors naming the file, never a crash") {
    const Folder dir;
    const engine::Mesh m = sample_mesh();
    const std::string le = perf::ply_bytes(m, perf::PlyEncoding::binary_little_endian);
    const std::string ascii = perf::ply_bytes(m, perf::PlyEncoding::ascii);
    engine::Mesh with_nan = m;
    with_nan.y[3] = std::numeric_limits<float>::quiet_NaN();
    const std::string stl = perf::stl_bytes(m, true);
    const std::string glb = perf::gltf_bytes(m, {});
    auto replace = [](std::string s, const std::string& from, const std::string& to) {
        const auto at = s.find(from);
        REQUIRE(at != std::string::npos);
        return s.replace(at, from.size(), to);
    };
    auto patch = [](std::string s, std::size_t at, const void* bytes, std::size_t n) {
        std::memcpy(s.data() + at, bytes, n);
        return s;
    };
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::uint32_t big = 1000000, past = 100000;
    const std::size_t body = le.find("end_header\n") + 11;
    const std::size_t faces = body + m.vertex_count() * 12;  // first face record: count byte, 3 ints
    // The first index accessor's data in the GLB: the last 4 x indices bytes of the buffer.
    const std::size_t glb_index = glb.size() - m.indices.size() * 4;
    struct Row {
        std::string file;
        std::string bytes;
        const char* message;
    };
    const std::vector<Row> rows = {
        {"truncated.ply", le.substr(0, le.size() - 5), "binary PLY body ends inside element 'face'"},
        {"truncated-ascii.ply", ascii.substr(0, ascii.size() - 40), "ASCII PLY body ends inside element 'face'"},
        {"count.ply", replace(le, "element vertex 42", "element vertex 900000042"), "element 'vertex' count 900000042"},
        {"count-ascii.ply", replace(ascii, "element face 80", "element face 8000000"), "element 'face' count 8000000"},
        {"index.ply", patch(le, faces + 1, &past, 4), "refers to vertex 100000, past the 42 vertices"},
        {"nan.ply", patch(le, body + 12, &nan, 4), "1 of 42 vertices is not finite (the first: vertex 1 = nan"},
        {"nan-ascii.ply", perf::ply_bytes(with_nan, perf::PlyEncoding::ascii), "1 of 42 vertices is not finite (the first: vertex 3"},
        {"points.ply", replace(replace(ascii, "element face 80", "element face 0"), "\n3 ", "\n"), "no triangles: the file holds only points/lines"},
        {"truncated.stl", stl.substr(0, stl.size() - 20), "binary STL header says 80 triangles"},
        {"count.stl", patch(stl, 80, &big, 4), "binary STL header says 1000000 triangles (50000084 bytes)"},
        {"nan.stl", patch(stl, 84 + 12 + 4, &nan, 4), "is not finite"},
        {"truncated-ascii.stl", perf::stl_bytes(m, false).substr(0, 300), "STL: "},
        {"truncated.glb", glb.substr(0, glb.size() - 64), "GLB header says"},
        {"count.glb", replace(glb, "\"count\":42,", "\"count\":99,"), "accessors[0]: byteOffset 0 + 99 elements of 12 bytes (stride 12) runs past bufferViews[0] (504 bytes)"},
        {"index.glb", patch(glb, glb_index, &past, 4), "the accessors define 80 triangles, Assimp read 79"},
        {"nan.glb", patch(glb, glb.find("BIN") + 3 + 1, &nan, 4), "is not finite"},
        {"json.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [", "glTF JSON does not parse"},
        {"version1.gltf", "{\"asset\": {\"version\": \"1.0\"}}", "glTF version 1.0"},
        {"empty.ply", "ply\nformat ascii 1.0\nend_header\n", "no triangles (the PLY file has no vertices)"},
        {"header.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float128 x\nend_header\n", "unknown PLY type 'float128'"},
    };
    for (const Row& r : rows) {
        CAPTURE(r.file);
        const std::string path = dir.write(r.file, r.bytes);
        const std::string msg = error_of(path);
        CAPTURE(msg);
        CHECK(msg.rfind(path + ":", 0) == 0);
        CHECK(msg.find(r.message) != std::string::npos);
        CHECK(msg.find('\n') == std::string::npos);
    }
}

TEST_CASE("mesh formats: an OBJ with only points and lines says so") {
    engine::Warnings w;
    CHECK_THROWS_WITH_AS(engine::load_mesh_bytes("v 0 0 0\nv 1 0 0\nv 0 1 0\np 1\nl 1 2\n", "pl.obj", "", w),
                         "pl.obj: no triangles: the file holds only points/lines", engine::InputError);
    CHECK_THROWS_WITH_AS(engine::load_mesh_bytes("# nothing\n", "e.obj", "", w), "e.obj: no triangles", engine::InputError);
}

TEST_CASE("mesh formats: text from the file with line breaks stays on one line in warnings and errors") {
    // A material named "two\nlines" (a JSON escape, so a real line break once parsed) whose
    // embedded texture does not decode: the warning quotes the name, escaped.
    const Folder dir;
    perf::GltfOptions o;
    o.binary = false;
    o.png = "not\nan image";
    std::string text = perf::gltf_bytes(sample_mesh(), o);
    const std::string key = "{\"pbrMetallicRoughness\"";
    REQUIRE(text.find(key) != std::string::npos);
    text.replace(text.find(key), key.size(), "{\"name\":\"two\\nlines\",\"pbrMetallicRoughness\"");
    engine::Warnings w;
    const engine::Mesh m = engine::load_mesh(dir.write("named.gltf", text), w);
    CHECK(m.triangle_count() == 80);
    REQUIRE(w.lines.size() == 1);
    CAPTURE(w.lines[0]);
    CHECK(w.lines[0].find("material 'two\\nlines': texture not used") != std::string::npos);
    CHECK(w.lines[0].find('\n') == std::string::npos);

    // Every control byte in a message becomes a visible escape.
    const engine::InputError e("f.obj", 3, std::string("a\nb\rc\td\x01" "e\x7f"));
    CHECK(std::string(e.what()) == "f.obj:3: a\\nb\\rc\\td\\x01e\\x7f");
    engine::Warnings w2;
    w2.add("x\ny");
    CHECK(w2.lines[0] == "x\\ny");
}
