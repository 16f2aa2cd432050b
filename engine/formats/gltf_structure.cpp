#include "engine/formats/gltf_structure.h"

#include "engine/error.h"

#include <nlohmann/json.hpp>

#include <array>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

namespace arbor::engine::formats {

namespace {

using nlohmann::json;

const json empty_array = json::array();

std::string at(const std::string& array, std::size_t i) { return array + "[" + std::to_string(i) + "]"; }

/// The fields of one document, each check throwing InputError("glTF: FIELD ...").
struct Checker {
    const json& doc;
    const std::string& name;

    [[noreturn]] void fail(const std::string& what) const { throw InputError(name, 0, "glTF: " + what); }

    const json& array(const char* key) const {
        return doc.contains(key) && doc[key].is_array() ? doc[key] : empty_array;
    }

    /// An optional unsigned integer member no larger than `max` (Assimp reads byte offsets and
    /// lengths as signed 32-bit integers: a negative one wraps, a larger one reads as 0).
    std::optional<std::uint64_t> uint_of(const json& obj, const char* key, const std::string& where,
                                         std::uint64_t max = std::numeric_limits<std::int32_t>::max()) const {
        if (!obj.is_object() || !obj.contains(key)) return std::nullopt;
        const json& v = obj[key];
        if (!v.is_number_unsigned() || v.get<std::uint64_t>() > max)
            fail(where + "." + key + " is " + v.dump().substr(0, 40) + " (an integer from 0 to " + std::to_string(max) + " is required)");
        return v.get<std::uint64_t>();
    }
    std::uint64_t required_uint(const json& obj, const char* key, const std::string& where,
                                std::uint64_t max = std::numeric_limits<std::int32_t>::max()) const {
        const auto v = uint_of(obj, key, where, max);
        if (!v) fail(where + " has no " + key);
        return *v;
    }

    /// An optional index into the top-level array `target`.
    std::optional<std::size_t> ref_of(const json& obj, const char* key, const char* target, const std::string& where) const {
        if (!obj.is_object() || !obj.contains(key)) return std::nullopt;
        const json& v = obj[key];
        const std::size_t n = array(target).size();
        if (!v.is_number_unsigned() || v.get<std::uint64_t>() >= n)
            fail(where + "." + key + " is " + v.dump().substr(0, 40) + ", not one of the " + std::to_string(n) + " " + target);
        return v.get<std::size_t>();
    }
    std::size_t required_ref(const json& obj, const char* key, const char* target, const std::string& where) const {
        const auto v = ref_of(obj, key, target, where);
        if (!v) fail(where + " has no " + key);
        return *v;
    }
    std::size_t ref_value(const json& v, const char* target, const std::string& where) const {
        const std::size_t n = array(target).size();
        if (!v.is_number_unsigned() || v.get<std::uint64_t>() >= n)
            fail(where + " is " + v.dump().substr(0, 40) + ", not one of the " + std::to_string(n) + " " + target);
        return v.get<std::size_t>();
    }

    // ---- buffers and views ----

    std::vector<std::uint64_t> buffer_bytes;  // what Assimp holds for each buffer (at most)
    std::vector<std::uint64_t> view_bytes;

    void data_uri(const json& obj, const std::string& where, bool image) const {
        if (!obj.is_object() || !obj.contains("uri") || !obj["uri"].is_string()) return;
        const std::string& uri = obj["uri"].get_ref<const std::string&>();
        if (uri.rfind("data:", 0) != 0) return;
        const auto comma = uri.find(',');
        // Assimp keeps the offsets of a data URI's parts in signed chars.
        if (comma == std::string::npos || comma > 100)
            fail(where + ".uri: a data URI whose header (before the ',') is not under 100 characters");
        if (image) {
            const std::string media = uri.substr(5, uri.find_first_of(";,", 5) - 5);
            if (media != "image/png" && media != "image/jpeg")
                fail(where + ".uri: a data URI of type '" + media + "' (glTF 2.0 allows image/png and image/jpeg)");
        }
    }

    void buffers(std::optional<std::uint64_t> glb_bin_bytes) {
        const json& list = array("buffers");
        for (std::size_t i = 0; i < list.size(); ++i) {
            const std::string where = at("buffers", i);
            if (!list[i].is_object()) fail(where + " is not an object");
            const std::uint64_t stated = uint_of(list[i], "byteLength", where).value_or(0);
            data_uri(list[i], where, false);
            // A GLB's buffers[0] is its BIN chunk, whatever the JSON says (Assimp 5.2).
            buffer_bytes.push_back(glb_bin_bytes && i == 0 ? *glb_bin_bytes : stated);
        }
        if (glb_bin_bytes && list.empty()) buffer_bytes.push_back(*glb_bin_bytes);
    }

    void buffer_views() {
        const json& list = array("bufferViews");
        for (std::size_t i = 0; i < list.size(); ++i) {
            const std::string where = at("bufferViews", i);
            const json& v = list[i];
            if (!v.is_object()) fail(where + " is not an object");
            if (!v.contains("buffer")) fail(where + " has no buffer");
            const std::uint64_t b = v["buffer"].is_number_unsigned() ? v["buffer"].get<std::uint64_t>() : ~0ull;
            if (b >= buffer_bytes.size())
                fail(where + ".buffer is " + v["buffer"].dump().substr(0, 40) + ", not one of the " + std::to_string(buffer_bytes.size()) +
                     " buffers");
            const std::uint64_t offset = uint_of(v, "byteOffset", where).value_or(0);
            const std::uint64_t length = required_uint(v, "byteLength", where);
            if (offset + length > buffer_bytes[b])
                fail(where + ": byteOffset " + std::to_string(offset) + " + byteLength " + std::to_string(length) + " runs past buffers[" +
                     std::to_string(b) + "] (" + std::to_string(buffer_bytes[b]) + " bytes)");
            if (const auto stride = uint_of(v, "byteStride", where); stride && (*stride < 4 || *stride > 252 || *stride % 4 != 0))
                fail(where + ".byteStride is " + std::to_string(*stride) + " (glTF 2.0: a multiple of 4 from 4 to 252)");
            view_bytes.push_back(length);
        }
    }

    // ---- accessors ----

    static unsigned component_bytes(std::uint64_t type) {
        switch (type) {
        case 5120:
        case 5121: return 1;
        case 5122:
        case 5123: return 2;
        case 5125:
        case 5126: return 4;
        default: return 0;
        }
    }
    static unsigned components(const std::string& type) {
        static const std::array<std::pair<const char*, unsigned>, 7> types = {
            {{"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4}, {"MAT2", 4}, {"MAT3", 9}, {"MAT4", 16}}};
        for (const auto& [n, c] : types)
            if (type == n) return c;
        return 0;
    }

    struct Accessor {
        std::uint64_t count = 0;
        std::uint64_t component_type = 0;
        std::string type;
    };
    std::vector<Accessor> acc;

    void accessors() {
        const json& list = array("accessors");
        const json& views = array("bufferViews");
        for (std::size_t i = 0; i < list.size(); ++i) {
            const std::string where = at("accessors", i);
            const json& a = list[i];
            if (!a.is_object()) fail(where + " is not an object");
            Accessor x;
            x.component_type = required_uint(a, "componentType", where, 0xffff);
            const unsigned csize = component_bytes(x.component_type);
            if (csize == 0) fail(where + ".componentType is " + std::to_string(x.component_type) + " (not a glTF 2.0 component type)");
            if (!a.contains("type") || !a["type"].is_string() || components(a["type"].get<std::string>()) == 0)
                fail(where + ".type is " + (a.contains("type") ? a["type"].dump().substr(0, 40) : std::string("missing")) +
                     " (SCALAR, VEC2, VEC3, VEC4, MAT2, MAT3 or MAT4)");
            x.type = a["type"].get<std::string>();
            x.count = required_uint(a, "count", where, 0xffffffffu);
            if (x.count == 0) fail(where + ".count is 0 (glTF 2.0: at least 1)");
            const std::uint64_t elem = std::uint64_t(csize) * components(x.type);
            const std::uint64_t offset = uint_of(a, "byteOffset", where).value_or(0);
            if (const auto v = ref_of(a, "bufferView", "bufferViews", where)) {
                const json& view = views[*v];
                const std::uint64_t stride = view.contains("byteStride") ? view["byteStride"].get<std::uint64_t>() : elem;
                // Assimp reads a sparse accessor's patched copy (packed) at its view's stride.
                if (a.contains("sparse") && stride != elem)
                    fail(where + ": a sparse accessor on bufferViews[" + std::to_string(*v) + "] of byteStride " + std::to_string(stride) +
                         ", not its " + std::to_string(elem) + "-byte elements");
                if (stride < elem)
                    fail(where + ": bufferViews[" + std::to_string(*v) + "].byteStride " + std::to_string(stride) + " is less than its " +
                         std::to_string(elem) + "-byte elements");
                // Assimp checks count x component size only, and then ignores byteOffset.
                if (offset + (x.count - 1) * stride + elem > view_bytes[*v])
                    fail(where + ": byteOffset " + std::to_string(offset) + " + " + std::to_string(x.count) + " elements of " +
                         std::to_string(elem) + " bytes (stride " + std::to_string(stride) + ") runs past bufferViews[" +
                         std::to_string(*v) + "] (" + std::to_string(view_bytes[*v]) + " bytes)");
            }
            // Without a view Assimp allocates count x element size of zeros for the sparse values.
            if (a.contains("sparse") && !a.contains("bufferView") && x.count * elem > gltf_max_sparse_bytes)
                fail(where + ": a sparse accessor without a bufferView of " + std::to_string(x.count) + " elements of " + std::to_string(elem) +
                     " bytes (more than " + std::to_string(gltf_max_sparse_bytes >> 20) + " MiB)");
            if (a.contains("sparse")) sparse(a["sparse"], where + ".sparse", x.count, elem);
            acc.push_back(x);
        }
    }

    void sparse(const json& s, const std::string& where, std::uint64_t count, std::uint64_t elem) const {
        if (!s.is_object()) fail(where + " is not an object");
        const std::uint64_t n = required_uint(s, "count", where, 0xffffffffu);
        if (n == 0 || n > count)
            fail(where + ".count is " + std::to_string(n) + " (from 1 to the accessor's count " + std::to_string(count) + ")");
        for (const char* part : {"indices", "values"}) {
            const std::string w = where + "." + part;
            if (!s.contains(part) || !s[part].is_object()) fail(where + " has no " + part + " object");
            const json& p = s[part];
            const std::size_t v = required_ref(p, "bufferView", "bufferViews", w);
            std::uint64_t size = elem;
            if (std::string(part) == "indices") {
                const std::uint64_t type = required_uint(p, "componentType", w, 0xffff);
                if (type != 5121 && type != 5123 && type != 5125)
                    fail(w + ".componentType is " + std::to_string(type) + " (5121, 5123 or 5125)");
                size = component_bytes(type);
            }
            const std::uint64_t offset = uint_of(p, "byteOffset", w).value_or(0);
            if (offset + n * size > view_bytes[v])
                fail(w + ": byteOffset " + std::to_string(offset) + " + " + std::to_string(n) + " x " + std::to_string(size) +
                     " bytes runs past bufferViews[" + std::to_string(v) + "] (" + std::to_string(view_bytes[v]) + " bytes)");
        }
    }

    // ---- meshes ----

    void accessor_is(std::size_t a, const char* type, std::initializer_list<std::uint64_t> component_types, const std::string& where,
                     const char* why) const {
        bool ok = acc[a].type == type;
        bool ct = false;
        for (std::uint64_t c : component_types) ct |= acc[a].component_type == c;
        if (!ok || !ct)
            fail(where + " is accessors[" + std::to_string(a) + "] of " + acc[a].type + " " + std::to_string(acc[a].component_type) + " (" +
                 why + ")");
    }

    /// What Assimp 5.2 makes of an attribute name: the first semantic it starts with, and the set
    /// after a '_' (atoi; 0 without one): "POSITIONS" is its POSITION, "TEXCOORD_00" its TEXCOORD_0.
    static std::pair<std::string, long> assimp_attribute(const std::string& key) {
        for (const char* s : {"POSITION", "NORMAL", "TANGENT", "TEXCOORD", "COLOR", "JOINTS", "JOINTMATRIX", "WEIGHTS"}) {
            const std::size_t n = std::strlen(s);
            if (key.compare(0, n, s) == 0) return {s, key.size() > n && key[n] == '_' ? std::atol(key.c_str() + n + 1) : 0};
        }
        return {"", -1};
    }

    void meshes() {
        const json& list = array("meshes");
        for (std::size_t m = 0; m < list.size(); ++m) {
            const std::string mw = at("meshes", m);
            if (!list[m].is_object() || !list[m].contains("primitives") || !list[m]["primitives"].is_array())
                fail(mw + " has no primitives array");
            const json& prims = list[m]["primitives"];
            for (std::size_t p = 0; p < prims.size(); ++p) {
                const std::string where = mw + ".primitives[" + std::to_string(p) + "]";
                const json& prim = prims[p];
                if (!prim.is_object() || !prim.contains("attributes") || !prim["attributes"].is_object())
                    fail(where + " has no attributes object");
                const std::uint64_t mode = uint_of(prim, "mode", where, 6).value_or(4);
                std::size_t joints = 0, weights = 0;
                std::optional<std::uint64_t> skin_count;
                for (const auto& [key, value] : prim["attributes"].items()) {
                    const std::string w = where + ".attributes." + key;
                    const std::size_t a = ref_value(value, "accessors", w);
                    const auto [semantic, set] = assimp_attribute(key);
                    if (set == 0 && (semantic == "POSITION" || semantic == "NORMAL"))
                        accessor_is(a, "VEC3", {5126}, w, "Assimp 5.2 reads VEC3 of 5126 (float) only");
                    if (set == 0 && semantic == "TEXCOORD") accessor_is(a, "VEC2", {5126}, w, "Assimp 5.2 reads VEC2 of 5126 (float) only");
                    const bool j = semantic == "JOINTS", wt = semantic == "WEIGHTS";
                    joints += j;
                    weights += wt;
                    if (j || wt) {
                        if (skin_count && *skin_count != acc[a].count)
                            fail(w + " has " + std::to_string(acc[a].count) + " elements, another JOINTS/WEIGHTS set " +
                                 std::to_string(*skin_count));
                        skin_count = acc[a].count;
                    }
                }
                if (joints != weights)
                    fail(where + " has " + std::to_string(joints) + " JOINTS and " + std::to_string(weights) +
                         " WEIGHTS sets (glTF 2.0 pairs them)");
                if (!prim["attributes"].contains("POSITION")) fail(where + " has no POSITION");
                std::uint64_t n = acc[required_ref(prim["attributes"], "POSITION", "accessors", where + ".attributes")].count;
                if (const auto i = ref_of(prim, "indices", "accessors", where)) {
                    accessor_is(*i, "SCALAR", {5121, 5123, 5125}, where + ".indices", "SCALAR of 5121, 5123 or 5125");
                    n = acc[*i].count;
                }
                // Assimp writes past its face array for shorter loops, strips and fans.
                if ((mode == 2 || mode == 3) && n < 2)
                    fail(where + ": a line loop or strip (mode " + std::to_string(mode) + ") of " + std::to_string(n) + " vertex (at least 2)");
                if ((mode == 5 || mode == 6) && n < 3)
                    fail(where + ": a triangle strip or fan (mode " + std::to_string(mode) + ") of " + std::to_string(n) +
                         " vertices (at least 3)");
                ref_of(prim, "material", "materials", where);
                if (prim.contains("targets")) {
                    if (!prim["targets"].is_array()) fail(where + ".targets is not an array");
                    for (std::size_t t = 0; t < prim["targets"].size(); ++t) {
                        const std::string tw = where + ".targets[" + std::to_string(t) + "]";
                        const json& target = prim["targets"][t];
                        if (!target.is_object()) fail(tw + " is not an object");
                        for (const auto& [key, value] : target.items()) {
                            // Assimp reads POSITION_1 as the second POSITION set and then uses only an empty first one.
                            for (const char* base : {"POSITION", "NORMAL", "TANGENT"})
                                if (key.rfind(base, 0) == 0 && key != base)
                                    fail(tw + "." + key + " (a morph target has POSITION, NORMAL and TANGENT only)");
                            ref_value(value, "accessors", tw + "." + key);
                        }
                    }
                }
            }
        }
    }

    // ---- nodes, scenes, skins ----

    void nodes() {
        const json& list = array("nodes");
        std::vector<std::int64_t> parent(list.size(), -1);
        std::vector<std::vector<std::size_t>> children(list.size());
        for (std::size_t i = 0; i < list.size(); ++i) {
            const std::string where = at("nodes", i);
            const json& node = list[i];
            if (!node.is_object()) fail(where + " is not an object");
            if (node.contains("children")) {
                if (!node["children"].is_array()) fail(where + ".children is not an array");
                for (std::size_t k = 0; k < node["children"].size(); ++k) {
                    const std::size_t c = ref_value(node["children"][k], "nodes", where + ".children[" + std::to_string(k) + "]");
                    if (parent[c] >= 0)
                        fail("nodes[" + std::to_string(c) + "] is a child of nodes[" + std::to_string(parent[c]) + "] and of " + where +
                             " (glTF 2.0 nodes form trees)");
                    parent[c] = std::int64_t(i);
                    children[i].push_back(c);
                }
            }
            ref_of(node, "mesh", "meshes", where);
            ref_of(node, "camera", "cameras", where);
            if (const auto s = ref_of(node, "skin", "skins", where)) {
                const std::string sw = at("skins", *s);
                const json& skin = array("skins")[*s];
                // Assimp reads the matrices of a used skin without checking that they exist.
                const std::size_t m = required_ref(skin, "inverseBindMatrices", "accessors", sw + " (used by " + where + ")");
                const std::size_t joints = skin.contains("joints") && skin["joints"].is_array() ? skin["joints"].size() : 0;
                accessor_is(m, "MAT4", {5126}, sw + ".inverseBindMatrices", "MAT4 of 5126 (float)");
                if (acc[m].count < joints)
                    fail(sw + ".inverseBindMatrices has " + std::to_string(acc[m].count) + " matrices for " + std::to_string(joints) +
                         " joints");
            }
        }
        // Every node is reached from a root (a node without a parent) once, no deeper than the limit.
        std::vector<bool> seen(list.size(), false);
        std::vector<std::pair<std::size_t, int>> stack;
        for (std::size_t r = 0; r < list.size(); ++r) {
            if (parent[r] >= 0) continue;
            stack.push_back({r, 1});
            while (!stack.empty()) {
                const auto [n, depth] = stack.back();
                stack.pop_back();
                seen[n] = true;
                if (depth > gltf_max_node_depth)
                    fail(at("nodes", n) + " is " + std::to_string(depth) + " levels deep (at most " + std::to_string(gltf_max_node_depth) + ")");
                for (std::size_t c : children[n]) stack.push_back({c, depth + 1});
            }
        }
        for (std::size_t n = 0; n < list.size(); ++n)
            if (!seen[n]) fail(at("nodes", n) + " is its own ancestor (a cycle of children)");
    }

    void scenes() {
        ref_of(doc, "scene", "scenes", "the document");
        const json& list = array("scenes");
        for (std::size_t i = 0; i < list.size(); ++i) {
            const std::string where = at("scenes", i);
            if (!list[i].is_object()) fail(where + " is not an object");
            if (list[i].contains("nodes") && list[i]["nodes"].is_array())
                for (std::size_t k = 0; k < list[i]["nodes"].size(); ++k)
                    ref_value(list[i]["nodes"][k], "nodes", where + ".nodes[" + std::to_string(k) + "]");
        }
        const json& skins = array("skins");
        for (std::size_t i = 0; i < skins.size(); ++i)
            if (skins[i].is_object() && skins[i].contains("joints") && skins[i]["joints"].is_array())
                for (std::size_t k = 0; k < skins[i]["joints"].size(); ++k)
                    ref_value(skins[i]["joints"][k], "nodes", at("skins", i) + ".joints[" + std::to_string(k) + "]");
    }

    // ---- animations ----

    void animations() {
        const json& list = array("animations");
        for (std::size_t i = 0; i < list.size(); ++i) {
            const std::string where = at("animations", i);
            const json& anim = list[i];
            if (!anim.is_object()) fail(where + " is not an object");
            const json& samplers = anim.contains("samplers") && anim["samplers"].is_array() ? anim["samplers"] : empty_array;
            for (std::size_t s = 0; s < samplers.size(); ++s) {
                const std::string sw = where + ".samplers[" + std::to_string(s) + "]";
                const std::size_t in = required_ref(samplers[s], "input", "accessors", sw);
                const std::size_t out = required_ref(samplers[s], "output", "accessors", sw);
                const bool cubic = samplers[s].contains("interpolation") && samplers[s]["interpolation"] == "CUBICSPLINE";
                // Assimp reads 3 outputs a key for a cubic spline having checked for 1.
                if (cubic && acc[out].count < 3 * acc[in].count)
                    fail(sw + ": a CUBICSPLINE output of " + std::to_string(acc[out].count) + " elements for " +
                         std::to_string(acc[in].count) + " keys (3 a key)");
            }
            const json& channels = anim.contains("channels") && anim["channels"].is_array() ? anim["channels"] : empty_array;
            for (std::size_t c = 0; c < channels.size(); ++c) {
                const std::string cw = where + ".channels[" + std::to_string(c) + "]";
                const json& ch = channels[c];
                if (!ch.is_object()) fail(cw + " is not an object");
                const std::size_t s = required_uint(ch, "sampler", cw);
                if (s >= samplers.size()) fail(cw + ".sampler is " + std::to_string(s) + ", not one of the " + std::to_string(samplers.size()) + " samplers");
                if (!ch.contains("target") || !ch["target"].is_object()) fail(cw + " has no target");
                // Without a node Assimp animates node 0, which may not exist.
                required_ref(ch["target"], "node", "nodes", cw + ".target");
            }
        }
    }

    // ---- textures and materials ----

    void textures() {
        const json& list = array("textures");
        for (std::size_t i = 0; i < list.size(); ++i) {
            ref_of(list[i], "source", "images", at("textures", i));
            ref_of(list[i], "sampler", "samplers", at("textures", i));
        }
        const json& images = array("images");
        for (std::size_t i = 0; i < images.size(); ++i) {
            ref_of(images[i], "bufferView", "bufferViews", at("images", i));
            data_uri(images[i], at("images", i), true);
        }
    }

    /// KHR_texture_transform objects anywhere in a material: Assimp indexes offset[0..1] and
    /// scale[0..1] as numbers without checking (a rapidjson assertion otherwise).
    void texture_transforms(const json& v, const std::string& where) const {
        if (v.is_object()) {
            for (const auto& [key, value] : v.items()) {
                if (key == "KHR_texture_transform" && value.is_object()) {
                    for (const char* pair : {"offset", "scale"})
                        if (value.contains(pair) &&
                            !(value[pair].is_array() && value[pair].size() == 2 && value[pair][0].is_number() && value[pair][1].is_number()))
                            fail(where + ".KHR_texture_transform." + pair + " is not an array of two numbers");
                    if (value.contains("rotation") && !value["rotation"].is_number())
                        fail(where + ".KHR_texture_transform.rotation is not a number");
                }
                texture_transforms(value, where + "." + key);
            }
        } else if (v.is_array()) {
            for (std::size_t i = 0; i < v.size(); ++i) texture_transforms(v[i], where + "[" + std::to_string(i) + "]");
        }
    }

    static int depth(const json& v) {
        int d = 0;
        if (v.is_object())
            for (const auto& [key, value] : v.items()) d = std::max(d, depth(value));
        else if (v.is_array())
            for (const auto& value : v) d = std::max(d, depth(value));
        else
            return 0;
        return d + 1;
    }

    void extras(const json& v, const std::string& where) const {
        if (v.is_object()) {
            for (const auto& [key, value] : v.items()) {
                const std::string w = where.empty() ? key : where + "." + key;
                if ((key == "extras" || key == "extensions") && depth(value) > gltf_max_extras_depth)
                    fail(w + " nests " + std::to_string(depth(value)) + " levels deep (at most " +
                         std::to_string(gltf_max_extras_depth) + ")");
                extras(value, w);
            }
        } else if (v.is_array()) {
            for (std::size_t i = 0; i < v.size(); ++i) extras(v[i], where + "[" + std::to_string(i) + "]");
        }
    }
};

}  // namespace

void check_json_depth(std::string_view text, const std::string& name) {
    int depth = 0;
    bool in_string = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (in_string) {
            if (c == '\\') ++i;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > gltf_max_json_depth)
                throw InputError(name, 0, "glTF JSON nests arrays and objects more than " + std::to_string(gltf_max_json_depth) + " levels deep");
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
}

void check_gltf_structure(const json& doc, std::optional<std::uint64_t> glb_bin_bytes, const std::string& name) {
    Checker c{doc, name, {}, {}, {}};
    c.extras(doc, "");
    c.buffers(glb_bin_bytes);
    c.buffer_views();
    c.accessors();
    c.meshes();
    c.nodes();
    c.scenes();
    c.animations();
    c.textures();
    const json& materials = c.array("materials");
    for (std::size_t i = 0; i < materials.size(); ++i) c.texture_transforms(materials[i], at("materials", i));
}

}  // namespace arbor::engine::formats
