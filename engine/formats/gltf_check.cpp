#include "engine/formats/gltf_check.h"

#include "engine/error.h"
#include "engine/formats/gltf_structure.h"

#include <nlohmann/json.hpp>

#include <cstring>
#include <optional>
#include <set>
#include <tuple>
#include <vector>

namespace arbor::engine::formats {

namespace {

std::uint32_t u32(std::string_view b, std::size_t at) {
    std::uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v |= std::uint32_t(static_cast<unsigned char>(b[at + std::size_t(k)])) << (8 * k);
    return v;
}

/// The JSON chunk of a GLB (after checking the header and the chunk lengths) and the length of
/// its BIN chunk (0 without one).
std::pair<std::string_view, std::uint64_t> glb_json(std::string_view b, const std::string& name) {
    if (b.size() < 20) throw InputError(name, 0, "GLB file of " + std::to_string(b.size()) + " bytes is shorter than its headers");
    const std::uint32_t version = u32(b, 4), length = u32(b, 8);
    if (version != 2) throw InputError(name, 0, "GLB version " + std::to_string(version) + " (only glTF 2.0 is read)");
    if (length != b.size())
        throw InputError(name, 0, "GLB header says " + std::to_string(length) + " bytes, the file has " + std::to_string(b.size()) +
                                      (length > b.size() ? " (truncated?)" : ""));
    const std::uint32_t json_length = u32(b, 12);
    if (std::memcmp(b.data() + 16, "JSON", 4) != 0) throw InputError(name, 0, "GLB: the first chunk is not JSON");
    if (json_length > b.size() - 20) throw InputError(name, 0, "GLB: the JSON chunk runs past the end of the file");
    std::size_t pos = 20 + std::size_t(json_length);
    pos = (pos + 3) & ~std::size_t(3);
    std::uint64_t bin = 0;
    if (pos < b.size()) {
        if (b.size() - pos < 8) throw InputError(name, 0, "GLB: a chunk header runs past the end of the file");
        bin = u32(b, pos);
        if (bin > b.size() - pos - 8) throw InputError(name, 0, "GLB: the binary chunk runs past the end of the file");
    }
    return {b.substr(20, json_length), bin};
}

std::uint64_t accessor_count(const nlohmann::json& accessors, const nlohmann::json& ref, const std::string& name) {
    if (!ref.is_number_unsigned() || ref.get<std::uint64_t>() >= accessors.size())
        throw InputError(name, 0, "glTF: a primitive refers to accessor " + ref.dump() + ", out of range");
    const nlohmann::json& a = accessors[ref.get<std::size_t>()];
    if (!a.is_object() || !a.contains("count") || !a["count"].is_number_unsigned())
        throw InputError(name, 0, "glTF: accessor " + ref.dump() + " has no count");
    return a["count"].get<std::uint64_t>();
}

}  // namespace

bool looks_like_glb(std::string_view b) { return b.size() >= 4 && b.substr(0, 4) == "glTF"; }

bool looks_like_json(std::string_view b) {
    for (char c : b) {
        if (c == ' ' || c == '\t' || c == '\r' || c == '\n') continue;
        return c == '{';
    }
    return false;
}

GltfCounts check_gltf(std::string_view bytes, const std::string& name) {
    std::string_view text = bytes;
    std::optional<std::uint64_t> bin;
    if (looks_like_glb(bytes)) std::tie(text, bin) = glb_json(bytes, name);
    check_json_depth(text, name);
    nlohmann::json j;
    try {
        // A key twice in one object: this parser keeps the last, Assimp's (rapidjson) finds the
        // first, so the checks below would pass what Assimp never reads. Refused.
        std::vector<std::set<std::string>> keys;
        std::string duplicate;
        bool nul = false;
        j = nlohmann::json::parse(text.begin(), text.end(), [&](int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
            using E = nlohmann::json::parse_event_t;
            if (event == E::object_start) keys.emplace_back();
            else if (event == E::object_end && !keys.empty()) keys.pop_back();
            else if (event == E::key && !keys.empty() && !keys.back().insert(parsed.get<std::string>()).second && duplicate.empty())
                duplicate = parsed.get<std::string>();
            // Assimp reads keys and strings as C strings: "POSITION\u0000x" is its POSITION, not ours.
            if ((event == E::key || event == E::value) && parsed.is_string() &&
                parsed.get_ref<const std::string&>().find('\0') != std::string::npos)
                nul = true;
            return true;
        });
        if (!duplicate.empty())
            throw InputError(name, 0, "glTF JSON has the key \"" + duplicate.substr(0, 64) + "\" twice in one object");
        if (nul) throw InputError(name, 0, "glTF JSON has a key or string holding \\u0000");
    } catch (const nlohmann::json::exception& e) {
        std::string what = e.what();
        for (char& c : what)
            if (c == '\n' || c == '\r') c = ' ';
        throw InputError(name, 0, "glTF JSON does not parse (" + what + ")");
    }
    if (!j.is_object() || !j.contains("asset") || !j["asset"].is_object() || !j["asset"].contains("version") ||
        !j["asset"]["version"].is_string())
        throw InputError(name, 0, "glTF: no asset.version (not a glTF file?)");
    const std::string version = j["asset"]["version"];
    if (version.rfind("2.", 0) != 0) throw InputError(name, 0, "glTF version " + version + " (only glTF 2.0 is read)");
    // glTF 2.0 allows two image types; Debian's Assimp 5 crashed (SEGV in its glTF2 importer) on
    // an embedded image with another mimeType (found by CI's mesh fuzzer).
    if (j.contains("images") && j["images"].is_array())
        for (const auto& image : j["images"])
            if (image.is_object() && image.contains("mimeType") &&
                !(image["mimeType"].is_string() && (image["mimeType"] == "image/png" || image["mimeType"] == "image/jpeg")))
                throw InputError(name, 0, "glTF: an image's mimeType is " + image["mimeType"].dump() + " (glTF 2.0 allows image/png and image/jpeg)");
    check_gltf_structure(j, bin, name);
    GltfCounts c;
    if (!j.contains("meshes")) return c;
    const nlohmann::json empty = nlohmann::json::array();
    const nlohmann::json& accessors = j.contains("accessors") && j["accessors"].is_array() ? j["accessors"] : empty;
    if (!j["meshes"].is_array()) throw InputError(name, 0, "glTF: meshes is not an array");
    for (std::size_t mi = 0; mi < j["meshes"].size(); ++mi) {
        const auto& mesh = j["meshes"][mi];
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array())
            throw InputError(name, 0, "glTF: a mesh without a primitives array");
        for (std::size_t pi = 0; pi < mesh["primitives"].size(); ++pi) {
            const auto& prim = mesh["primitives"][pi];
            if (!prim.is_object() || !prim.contains("attributes") || !prim["attributes"].is_object() ||
                !prim["attributes"].contains("POSITION"))
                throw InputError(name, 0, "glTF: a primitive without POSITION");
            const int mode = prim.contains("mode") && prim["mode"].is_number_integer() ? prim["mode"].get<int>() : 4;
            const std::uint64_t n = prim.contains("indices") ? accessor_count(accessors, prim["indices"], name)
                                                              : accessor_count(accessors, prim["attributes"]["POSITION"], name);
            if (mode == 4) c.triangles += n / 3;
            else if (mode == 5 || mode == 6) c.triangles += n >= 3 ? n - 2 : 0;
            else if (c.point_line_prims++ == 0) {
                static const char* const kinds[] = {"points", "lines", "line loop", "line strip"};
                c.first_point_line = "meshes[" + std::to_string(mi) + "].primitives[" + std::to_string(pi) +
                                     "] (mode " + std::to_string(mode) + ": " +
                                     (mode >= 0 && mode < 4 ? kinds[mode] : "?") + ")";
            }
        }
    }
    return c;
}

}  // namespace arbor::engine::formats
