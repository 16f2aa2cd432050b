// The glTF fields Assimp 5.2.5 trusts, checked before it reads them (engine/formats/gltf_structure):
// each broken file gets a one-line error naming the field; each of the rules' valid neighbours
// (a sparse accessor, a skin, a cubic-spline animation, a 512-level node chain, ...) still loads.
#include "engine/error.h"
#include "engine/formats/gltf_structure.h"
#include "engine/mesh_loader.h"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <cstring>
#include <functional>
#include <string>
#include <vector>

using nlohmann::json;
using namespace arbor;
using engine::formats::gltf_max_extras_depth;
using engine::formats::gltf_max_node_depth;

namespace {

void put_u32(std::string& s, std::uint32_t v) {
    for (int k = 0; k < 4; ++k) s += char((v >> (8 * k)) & 0xff);
}
void put_f32(std::string& s, float f) {
    std::uint32_t v;
    std::memcpy(&v, &f, 4);
    put_u32(s, v);
}

/// A quad: 4 positions (view 0, 48 bytes), 4 normals (view 1), 6 uint16 indices (view 2, 12 bytes).
std::string quad_bin() {
    std::string b;
    for (float p : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 1.f, 1.f, 0.f, 0.f, 1.f, 0.f}) put_f32(b, p);
    for (int v = 0; v < 4; ++v)
        for (float n : {0.f, 0.f, 1.f}) put_f32(b, n);
    for (int i : {0, 1, 2, 0, 2, 3}) b += char(i), b += char(0);
    return b;
}

json quad_doc() {
    return json::parse(R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
                      {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 96, "byteLength": 12}],
        "buffers": [{"byteLength": 108}]})");
}

std::string glb_text(std::string j, std::string bin) {
    while (j.size() % 4) j += ' ';
    while (bin.size() % 4) bin += '\0';
    std::string out = "glTF";
    put_u32(out, 2);
    put_u32(out, std::uint32_t(12 + 8 + j.size() + (bin.empty() ? 0 : 8 + bin.size())));
    put_u32(out, std::uint32_t(j.size()));
    out += "JSON" + j;
    if (!bin.empty()) {
        put_u32(out, std::uint32_t(bin.size()));
        out += std::string("BIN\0", 4) + bin;
    }
    return out;
}

std::string glb(const json& doc, const std::string& bin) { return glb_text(doc.dump(), bin); }

std::string load(const std::string& bytes, const std::string& name = "x.glb") {
    engine::Warnings w;
    try {
        const engine::Mesh m = engine::load_mesh_bytes(bytes, name, "", w, false);
        return "loaded " + std::to_string(m.triangle_count());
    } catch (const engine::InputError& e) {
        return e.what();
    }
}

std::string with(const std::function<void(json&)>& edit) {
    json d = quad_doc();
    edit(d);
    return glb(d, quad_bin());
}

/// A node chain `depth` levels deep with the mesh at its end.
json chain(int depth) {
    json d = quad_doc();
    d["nodes"] = json::array();
    for (int i = 0; i + 1 < depth; ++i) d["nodes"].push_back({{"children", {i + 1}}});
    d["nodes"].push_back({{"mesh", 0}});
    return d;
}

/// `depth` nested arrays.
json nested(int depth) {
    json v = json::array();
    for (int i = 1; i < depth; ++i) v = json::array({v});
    return v;
}

}  // namespace

TEST_CASE("glTF structure: fields Assimp 5.2 trusts are checked before it reads them, the error names the field") {
    REQUIRE(load(glb(quad_doc(), quad_bin())) == "loaded 2");
    struct Row {
        std::string what;
        std::string bytes;
        const char* message;
    };
    const std::vector<Row> rows = {
        // An accessor's elements past its view: Assimp checks count x component size and ignores byteOffset (read past the buffer).
        {"accessor offset", with([](json& d) { d["accessors"][1]["byteOffset"] = 32; }),
         "accessors[1]: byteOffset 32 + 4 elements of 12 bytes (stride 12) runs past bufferViews[1] (48 bytes)"},
        {"negative offset", with([](json& d) { d["accessors"][0]["byteOffset"] = -48; }),
         "accessors[0].byteOffset is -48 (an integer from 0 to 2147483647 is required)"},
        {"view past buffer", glb(quad_doc(), quad_bin().substr(0, 48)),
         "bufferViews[1]: byteOffset 48 + byteLength 48 runs past buffers[0] (48 bytes)"},
        {"stride", with([](json& d) { d["bufferViews"][1]["byteStride"] = 4; }),
         "accessors[1]: bufferViews[1].byteStride 4 is less than its 12-byte elements"},
        {"stride range", with([](json& d) { d["bufferViews"][2]["byteStride"] = 2; }), "bufferViews[2].byteStride is 2"},
        {"component type", with([](json& d) { d["accessors"][0]["componentType"] = 5127; }), "accessors[0].componentType is 5127"},
        {"type", with([](json& d) { d["accessors"][0]["type"] = "VEC7"; }), "accessors[0].type is \"VEC7\""},
        {"count 0", with([](json& d) { d["accessors"][2]["count"] = 0; }), "accessors[2].count is 0"},
        {"float indices", with([](json& d) { d["accessors"][2]["componentType"] = 5126, d["accessors"][2]["count"] = 3; }),
         "meshes[0].primitives[0].indices is accessors[2] of SCALAR 5126"},
        {"short positions", with([](json& d) { d["accessors"][0]["componentType"] = 5123; }),
         "meshes[0].primitives[0].attributes.POSITION is accessors[0] of VEC3 5123"},
        {"attribute prefix", with([](json& d) {
             d["accessors"][1]["type"] = "VEC2";
             d["meshes"][0]["primitives"][0]["attributes"].erase("NORMAL");
             d["meshes"][0]["primitives"][0]["attributes"]["NORMALS"] = 1;
         }),
         "meshes[0].primitives[0].attributes.NORMALS is accessors[1] of VEC2 5126"},
        // Sparse accessors: Assimp dereferences the missing views (SEGV).
        {"sparse indices view", with([](json& d) {
             d["accessors"][0]["sparse"] = json::parse(R"({"count": 1, "indices": {"componentType": 5125}, "values": {"bufferView": 1}})");
         }),
         "accessors[0].sparse.indices has no bufferView"},
        {"sparse values view", with([](json& d) {
             d["accessors"][0]["sparse"] = json::parse(R"({"count": 1, "indices": {"bufferView": 2, "componentType": 5123}, "values": {}})");
         }),
         "accessors[0].sparse.values has no bufferView"},
        {"sparse no indices",
         with([](json& d) { d["accessors"][0]["sparse"] = json::parse(R"({"count": 1, "values": {"bufferView": 1}})"); }),
         "accessors[0].sparse has no indices object"},
        {"sparse count", with([](json& d) {
             d["accessors"][0]["sparse"] =
                 json::parse(R"({"count": 5, "indices": {"bufferView": 2, "componentType": 5123}, "values": {"bufferView": 1}})");
         }),
         "accessors[0].sparse.count is 5 (from 1 to the accessor's count 4)"},
        {"sparse strided", with([](json& d) {
             d["bufferViews"][1]["byteStride"] = 16, d["bufferViews"][1]["byteLength"] = 60, d["bufferViews"][1]["byteOffset"] = 36;
             d["accessors"][1]["sparse"] =
                 json::parse(R"({"count": 1, "indices": {"bufferView": 2, "componentType": 5123}, "values": {"bufferView": 0}})");
         }),
         "accessors[1]: a sparse accessor on bufferViews[1] of byteStride 16, not its 12-byte elements"},
        {"sparse huge", with([](json& d) {
             d["accessors"].push_back(json::parse(
                 R"({"componentType": 5126, "count": 4000000000, "type": "SCALAR", "sparse": {"count": 1, "indices": {"bufferView": 2, "componentType": 5123}, "values": {"bufferView": 0}}})"));
         }),
         "accessors[3]: a sparse accessor without a bufferView of 4000000000 elements of 4 bytes (more than 256 MiB)"},
        // Short loops, strips and fans: Assimp writes past its face array or allocates 2^32 faces.
        {"line loop", with([](json& d) { d["meshes"][0]["primitives"][0]["mode"] = 2, d["accessors"][2]["count"] = 1; }),
         "meshes[0].primitives[0]: a line loop or strip (mode 2) of 1 vertex"},
        {"fan", with([](json& d) { d["meshes"][0]["primitives"][0]["mode"] = 6, d["accessors"][2]["count"] = 2; }),
         "meshes[0].primitives[0]: a triangle strip or fan (mode 6) of 2 vertices"},
        {"mode", with([](json& d) { d["meshes"][0]["primitives"][0]["mode"] = 9; }), "meshes[0].primitives[0].mode is 9"},
        // Morph targets named POSITION_1 (Assimp: SEGV on the empty first set; POSITION_<huge>: a huge vector).
        {"target", with([](json& d) { d["meshes"][0]["primitives"][0]["targets"] = json::parse(R"([{"NORMAL_3": 1}])"); }),
         "meshes[0].primitives[0].targets[0].NORMAL_3 (a morph target has POSITION, NORMAL and TANGENT only)"},
        // Skins: no matrices (SEGV), fewer matrices than joints (read past them), unpaired JOINTS/WEIGHTS (heap corruption).
        {"skin matrices", with([](json& d) { d["nodes"][0]["skin"] = 0, d["skins"] = json::parse(R"([{"joints": [0]}])"); }),
         "skins[0] (used by nodes[0]) has no inverseBindMatrices"},
        {"skin joints", with([](json& d) {
             d["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 96}});
             d["accessors"].push_back({{"bufferView", 3}, {"componentType", 5126}, {"count", 1}, {"type", "MAT4"}});
             d["nodes"][0]["skin"] = 0, d["skins"] = json::parse(R"([{"joints": [0, 0], "inverseBindMatrices": 3}])");
         }),
         "skins[0].inverseBindMatrices has 1 matrices for 2 joints"},
        {"joints weights", with([](json& d) {
             d["accessors"].push_back({{"bufferView", 1}, {"componentType", 5126}, {"count", 3}, {"type", "VEC4"}});
             d["accessors"].push_back({{"bufferView", 2}, {"componentType", 5121}, {"count", 3}, {"type", "VEC4"}});
             d["meshes"][0]["primitives"][0]["attributes"].update({{"WEIGHTS_0", 3}, {"WEIGHTS_1", 3}, {"JOINTS_0", 4}});
         }),
         "meshes[0].primitives[0] has 1 JOINTS and 2 WEIGHTS sets"},
        // Animations: a channel without a node (SEGV), a cubic spline with one output a key (huge allocation).
        {"channel node", with([](json& d) {
             d["accessors"].push_back({{"bufferView", 0}, {"componentType", 5126}, {"count", 2}, {"type", "SCALAR"}});
             d["animations"] = json::parse(R"([{"samplers": [{"input": 3, "output": 0}], "channels": [{"sampler": 0, "target": {"path": "translation"}}]}])");
         }),
         "animations[0].channels[0].target has no node"},
        {"cubic spline", with([](json& d) {
             d["accessors"].push_back({{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "SCALAR"}});
             d["animations"] = json::parse(
                 R"([{"samplers": [{"input": 3, "output": 3, "interpolation": "CUBICSPLINE"}], "channels": [{"sampler": 0, "target": {"node": 0, "path": "weights"}}]}])");
         }),
         "animations[0].samplers[0]: a CUBICSPLINE output of 4 elements for 4 keys (3 a key)"},
        // Images and data URIs: a media type without '/' (SEGV), a header Assimp's char offsets cannot hold.
        {"image data URI", with([](json& d) { d["images"] = json::parse(R"([{"uri": "data:imagepng;base64,iVBORw0K"}])"); }),
         "images[0].uri: a data URI of type 'imagepng'"},
        {"long data URI", with([](json& d) { d["buffers"][0]["uri"] = "data:" + std::string(140, 'x') + ";base64,AAAA"; }),
         "buffers[0].uri: a data URI whose header (before the ',') is not under 100 characters"},
        {"texture transform", with([](json& d) {
             d["materials"] = json::parse(
                 R"([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {"offset": []}}}}}])");
         }),
         "materials[0].pbrMetallicRoughness.baseColorTexture.extensions.KHR_texture_transform.offset is not an array of two numbers"},
        // Node graphs: shared children (2^n nodes), cycles, deep chains (stack overflow), deep extras (exponential time).
        {"two parents", with([](json& d) { d["nodes"] = json::parse(R"([{"children": [2]}, {"children": [2]}, {"mesh": 0}])"); }),
         "nodes[2] is a child of nodes[0] and of nodes[1] (glTF 2.0 nodes form trees)"},
        {"cycle", with([](json& d) { d["nodes"] = json::parse(R"([{"mesh": 0}, {"children": [2]}, {"children": [1]}])"); }),
         "nodes[1] is its own ancestor"},
        {"deep chain", glb(chain(gltf_max_node_depth + 1), quad_bin()), "nodes[512] is 513 levels deep (at most 512)"},
        {"deep extras", with([](json& d) { d["nodes"][0]["extras"] = json::object({{"a", nested(gltf_max_extras_depth)}}); }),
         "nodes[0].extras nests 9 levels deep (at most 8)"},
        {"child index", with([](json& d) { d["nodes"][0]["children"] = {7}; }), "nodes[0].children[0] is 7, not one of the 1 nodes"},
    };
    for (const Row& r : rows) {
        CAPTURE(r.what);
        const std::string msg = load(r.bytes);
        CAPTURE(msg);
        CHECK(msg.rfind("x.glb: glTF: ", 0) == 0);
        CHECK(msg.find(r.message) != std::string::npos);
        CHECK(msg.find('\n') == std::string::npos);
    }
    // A key twice in one object (nlohmann keeps the last, Assimp reads the first: a crashing first
    // "accessors" behind a sound second one).
    json bad = quad_doc()["accessors"];
    bad[0]["sparse"] = json::parse(R"({"count": 1, "values": {"bufferView": 1}})");
    std::string twice = quad_doc().dump();
    twice.insert(1, "\"accessors\":" + bad.dump() + ",");
    CHECK(load(glb_text(twice, quad_bin())) == "x.glb: glTF JSON has the key \"accessors\" twice in one object");
    // An escaped NUL in a key: Assimp reads "NORMAL\u0000x" as NORMAL (here a VEC2 it would misread).
    json n = quad_doc();
    n["accessors"][1]["type"] = "VEC2";
    std::string nul = n.dump();
    nul.replace(nul.find("\"NORMAL\""), 8, "\"NORMAL\\u0000x\"");
    CHECK(load(glb_text(nul, quad_bin())) == "x.glb: glTF JSON has a key or string holding \\u0000");
    // JSON nested past the limit, refused before any parser recurses into it.
    json d = quad_doc();
    std::string text = d.dump();
    text.insert(text.size() - 1, ",\"extras\":" + std::string(100000, '[') + std::string(100000, ']'));
    CHECK(load(text, "x.gltf") == "x.gltf: glTF JSON nests arrays and objects more than 64 levels deep");
}

TEST_CASE("glTF structure: the valid neighbours of each rule still load") {
    // A sparse accessor moving vertex 2 (Assimp patches it in).
    std::string bin = quad_bin();
    put_u32(bin, 2);
    for (float c : {1.f, 2.f, 0.f}) put_f32(bin, c);
    json d = quad_doc();
    d["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 108}, {"byteLength", 4}});
    d["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 112}, {"byteLength", 12}});
    d["buffers"][0]["byteLength"] = 124;
    d["accessors"][0]["sparse"] = json::parse(R"({"count": 1, "indices": {"bufferView": 3, "componentType": 5125}, "values": {"bufferView": 4}})");
    d["accessors"][0]["max"] = {1, 2, 0};
    engine::Warnings w;
    const engine::Mesh m = engine::load_mesh_bytes(glb(d, bin), "sparse.glb", "", w, false);
    CHECK(m.triangle_count() == 2);
    CHECK(m.bounds.hi.y == 2.0f);

    // A skin with one matrix a joint and paired JOINTS/WEIGHTS; a cubic spline with 3 outputs a key;
    // a 512-level chain; extras 8 levels deep; a texture transform of two numbers each.
    std::string skin_bin = quad_bin();
    for (int k = 0; k < 16; ++k) put_f32(skin_bin, k % 5 == 0 ? 1.f : 0.f);  // identity, at 108
    for (int v = 0; v < 4; ++v) put_f32(skin_bin, 1.f), put_f32(skin_bin, 0.f), put_f32(skin_bin, 0.f), put_f32(skin_bin, 0.f);  // weights, at 172
    for (int v = 0; v < 4; ++v) put_u32(skin_bin, 0);  // joints (4 x ubyte), at 236
    json s = quad_doc();
    s["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 108}, {"byteLength", 64}});
    s["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 172}, {"byteLength", 64}});
    s["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 236}, {"byteLength", 16}});
    s["buffers"][0]["byteLength"] = 252;
    s["accessors"].push_back({{"bufferView", 3}, {"componentType", 5126}, {"count", 1}, {"type", "MAT4"}});
    s["accessors"].push_back({{"bufferView", 4}, {"componentType", 5126}, {"count", 4}, {"type", "VEC4"}});
    s["accessors"].push_back({{"bufferView", 5}, {"componentType", 5121}, {"count", 4}, {"type", "VEC4"}});
    s["meshes"][0]["primitives"][0]["attributes"].update({{"WEIGHTS_0", 4}, {"JOINTS_0", 5}});
    s["nodes"] = json::parse(R"([{"children": [1]}, {"mesh": 0, "skin": 0}])");
    s["skins"] = json::parse(R"([{"joints": [0], "inverseBindMatrices": 3}])");
    CHECK(load(glb(s, skin_bin)) == "loaded 2");

    CHECK(load(with([](json& a) {
              a["accessors"].push_back({{"bufferView", 0}, {"componentType", 5126}, {"count", 1}, {"type", "SCALAR"}});
              a["animations"] = json::parse(
                  R"([{"samplers": [{"input": 3, "output": 1, "interpolation": "CUBICSPLINE"}], "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}]}])");
          })) == "loaded 2");
    CHECK(load(glb(chain(gltf_max_node_depth), quad_bin())) == "loaded 2");
    CHECK(load(with([](json& a) { a["nodes"][0]["extras"] = json::object({{"a", nested(gltf_max_extras_depth - 1)}}); })) == "loaded 2");
    CHECK(load(with([](json& a) {
              a["extensionsUsed"] = {"KHR_texture_transform"};
              a["materials"] = json::parse(
                  R"([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {"offset": [0.5, 0], "scale": [2, 2], "rotation": 1}}}}}])");
              a["textures"] = json::parse(R"([{}])");
              a["meshes"][0]["primitives"][0]["material"] = 0;
          })) == "loaded 2");
    // A line strip beside the triangles (2 vertices: the shortest allowed).
    CHECK(load(with([](json& a) {
              a["accessors"].push_back({{"bufferView", 2}, {"componentType", 5123}, {"count", 2}, {"type", "SCALAR"}});
              a["meshes"][0]["primitives"].push_back({{"attributes", {{"POSITION", 0}}}, {"indices", 3}, {"mode", 3}});
          })) == "loaded 2");
}

TEST_CASE(
    "glTF structure: primitives of points or lines beside triangles are warned about by name, strips and fans read") {
    // The quad's indices once more as a line strip (mode 3) and as points (mode 0), after the triangles.
    const std::string bytes = with([](json& d) {
        auto& prims = d["meshes"][0]["primitives"];
        prims.push_back({{"attributes", {{"POSITION", 0}}}, {"indices", 2}, {"mode", 3}});
        prims.push_back({{"attributes", {{"POSITION", 0}}}, {"mode", 0}});
    });
    engine::Warnings w;
    const engine::Mesh m = engine::load_mesh_bytes(bytes, "mixed.glb", "", w, false);
    CHECK(m.triangle_count() == 2);
    REQUIRE(w.lines.size() == 1);
    CHECK(w.lines[0] ==
          "mixed.glb: glTF: 2 primitives of points or lines not read (no surfaces), the first: "
          "meshes[0].primitives[1] (mode 3: line strip)");
    // A strip (mode 5) and a fan (mode 6) over the 6 indices: 4 triangles each, no warning.
    for (const int mode : {5, 6}) {
        CAPTURE(mode);
        engine::Warnings none;
        const engine::Mesh s = engine::load_mesh_bytes(
            with([mode](json& d) { d["meshes"][0]["primitives"][0]["mode"] = mode; }), "strip.glb", "", none, false);
        CHECK(s.triangle_count() == 4);
        CHECK(none.lines.empty());
    }
}
