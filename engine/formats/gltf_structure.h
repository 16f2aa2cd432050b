#pragma once
/// The glTF 2.0 fields Debian's Assimp 5.2.5 trusts without checking, checked before it reads
/// them: each of these once crashed, hung or misread it (SEGV, abort, FPE, stack overflow,
/// exponential time, reads past a buffer; tests/fuzz/regressions/mesh/assimp-gltf2-*). The rules
/// are glTF 2.0's own (or tighter where Assimp needs it), each error naming the field.
#include <nlohmann/json_fwd.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace arbor::engine::formats {

/// Deepest nesting of arrays and objects the JSON may have (Assimp's JSON reader recurses).
inline constexpr int gltf_max_json_depth = 64;
/// Deepest nesting inside an "extras" or "extensions" value (Assimp copies node and scene
/// extras into its metadata in time exponential in their depth: 32 levels took minutes).
inline constexpr int gltf_max_extras_depth = 8;
/// Deepest node hierarchy (Assimp reads and converts it recursively: 20,000 levels overflowed
/// an 8 MB stack).
inline constexpr int gltf_max_node_depth = 512;

/// Largest sparse accessor without a bufferView (Assimp allocates it whole before reading it).
inline constexpr std::uint64_t gltf_max_sparse_bytes = std::uint64_t(1) << 28;

/// InputError naming `name` when the text nests arrays and objects deeper than
/// gltf_max_json_depth (strings skipped); run before any parser sees the text.
void check_json_depth(std::string_view text, const std::string& name);

/// InputError naming `name` and the field (e.g. "accessors[2].byteOffset") for the first rule
/// the document breaks. `glb_bin_bytes`: the GLB's BIN chunk length (0 without one), which is
/// what Assimp reads as buffers[0] of a GLB; nullopt for a .gltf.
void check_gltf_structure(const nlohmann::json& doc, std::optional<std::uint64_t> glb_bin_bytes, const std::string& name);

}  // namespace arbor::engine::formats
