#pragma once
/// Procedural meshes that need no files: for the embedded scenes, tests and benchmarks.
#include "engine/mesh.h"

#include <cstdint>

namespace arbor::engine {

/// Closed icosphere: 20 * 4^subdivisions triangles, vertices shared (indexed), consistently
/// wound (normals outward). With jitter > 0 every vertex radius is scaled by a factor in
/// [1 - jitter, 1 + jitter] drawn from `seed`, keeping the mesh closed.
Mesh make_icosphere(Vec3f center, float radius, int subdivisions, float jitter = 0.0f, std::uint32_t seed = 1);
/// Closed axis-aligned box [lo, hi], 12 triangles.
Mesh make_box(Vec3f lo, Vec3f hi);
/// Square in the plane y = height, centred at (cx, cz), 2 triangles facing +y.
Mesh make_ground(float height, float cx, float cz, float half_size);
/// Closed torus around the y axis: `rings` x `sides` quads split into triangles.
Mesh make_torus(Vec3f center, float major_radius, float minor_radius, int rings, int sides);
/// A mesh with a single material attached to all its triangles.
Mesh with_material(Mesh mesh, const Material& m);

}  // namespace arbor::engine
