#pragma once
/// The bodies of the libFuzzer harnesses, in a library of their own so that the doctest suite can
/// replay every committed regression input through exactly the code the fuzzers run.
///
/// Each target accepts any bytes. Bad input must end in engine::InputError (caught here); anything
/// else is a finding: a crash or sanitizer report, an unexpected exception, or a FuzzFinding thrown
/// when a result breaks a contract (a loaded mesh with an index out of range, a structure whose
/// answer differs from brute force, an untraceable ray that hits).
#include "accel/interface/accel.h"
#include "engine/mesh.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>

namespace arbor::fuzz {

struct FuzzFinding : std::logic_error {
    using std::logic_error::logic_error;
};

/// The contract every target checks a structure by: on every path `a` offers, closest hits agree
/// with brute force over `tris` (spec/rayfile.md rule), any-hit answers hit exactly when brute's
/// closest does, with t in [tnear, tfar], untraceable rays miss, and `a` dropped as many non-finite
/// triangles as brute. Throws FuzzFinding naming the structure, path and ray otherwise.
void check_structure(const accel::Accel& a, const accel::TriangleView& tris, std::span<const accel::Ray> rays);

/// The fixed scene fuzz_rays traces its rays through: a sphere, a box and a ground
/// (arbor_extreme_search searches it too).
const engine::Mesh& ray_scene();

/// The OBJ loader (engine::load_obj_text) on `data` as a file's text; a mesh that loads is
/// checked and, when small, traced by every structure and path against brute force.
void fuzz_obj(const std::uint8_t* data, std::size_t size);
/// The mesh loader's entry for every format (engine::load_mesh_bytes: format detection, the PLY,
/// STL and glTF checks, Assimp, the shared validation) on `data` as a file's bytes, nothing else
/// read; a mesh that loads is checked as in fuzz_obj.
void fuzz_mesh(const std::uint8_t* data, std::size_t size);
/// The ray- and hit-file readers (engine::parse_rays/parse_hits) on `data` as a file's bytes;
/// rays that parse are traced through a fixed scene by every structure and path against brute force.
void fuzz_rays(const std::uint8_t* data, std::size_t size);
/// The viewer's message parser (view::parse_client_message) on `data` as a WebSocket text message:
/// a message that parses must hold values the server can use (finite camera with a view direction,
/// settings within the limits); a refused one must say why. The same bytes also go through the
/// server's request-head parser and WebSocket frame reader (view/http.h, view/websocket.h).
void fuzz_view_message(const std::uint8_t* data, std::size_t size);

}  // namespace arbor::fuzz
