#pragma once
/// The checks every mesh goes through after its format's reader, whatever the format: every
/// vertex finite (a file with non-finite coordinates is refused, with how many and the first one),
/// every index in range (positions, normals, texture coordinates, materials, textures), at least
/// one triangle. The bounds are computed here.
#include "engine/mesh.h"

#include <string>

namespace arbor::engine {

/// InputError "NAME: problem" on the first failed check; `no_triangles_why` is added to the
/// "no triangles" message (e.g. ": the file holds only points/lines").
void validate_mesh(Mesh& mesh, const std::string& name, const std::string& no_triangles_why = "");

}  // namespace arbor::engine
