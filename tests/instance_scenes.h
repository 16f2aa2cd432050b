#pragma once
/// Scenes of the instance tests: meshes placed by transforms of every kind (rotations about
/// skew axes, mirrors, non-uniform scales, shears), the same scene flattened (each placed copy's
/// vertices carried over in double, then rounded to float), and the distance of a hit from its
/// triangle's edges (the tests leave out rays within 1e-6 of the scene's diagonal of an edge).
#include "engine/mesh.h"

#include <arbor/arbor.h>

#include <array>
#include <vector>

namespace arbor::testing {

using Transform = std::array<double, 12>;

/// A rotation by `angle` radians about the unit axis (ax, ay, az), scaled by (sx, sy, sz) first
/// (negative: a mirror), then moved by (tx, ty, tz).
Transform make_transform(double angle, std::array<double, 3> axis, std::array<double, 3> scale, std::array<double, 3> move);
/// t with its 3x3 part multiplied on the right by a shear of x by `k` times y.
Transform sheared(Transform t, double k);

/// Mesh m carried by t, vertex by vertex in double, rounded to float once.
engine::Mesh flatten(const engine::Mesh& m, const Transform& t);

/// Adds mesh m to a public scene (packed arrays); returns its geometry id.
std::uint32_t add(Scene& s, const engine::Mesh& m);

/// The smallest distance from the point of barycentrics (u, v) on triangle `prim` of `m` to the
/// triangle's edges (each barycentric times the height over its edge), in double.
double edge_distance(const engine::Mesh& m, std::uint32_t prim, float u, float v);

/// The placements of the stiff tests: rotations about skew axes, a mirror, non-uniform scales and
/// a shear, spread out so that no two copies overlap in a box of half-size 1.5 around their origin.
std::vector<Transform> stiff_transforms();

}  // namespace arbor::testing
