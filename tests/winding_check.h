#pragma once
/// Helpers of the winding-number tests: the long-double oracle, the stiff meshes, and the checks
/// of a winding tree against the oracle and against its own error bound.
#include "accel/core/winding_tree.h"
#include "engine/mesh.h"

#include <cstdint>
#include <string>
#include <vector>

namespace arbor::testing {

/// The oracle: every finite triangle's solid angle by Van Oosterom & Strackee, each term and the
/// sum in long double, written apart from accel/core/solid_angle.h. Same convention for a point
/// exactly in a triangle's plane: 0, decided in exact integer arithmetic. (The differences of
/// float coordinates are exact in long double while their exponents are within 39 of each other,
/// which every test point keeps.)
long double oracle_winding(const accel::TriangleView& tris, const accel::Vec3f& p);

/// A closed axis-aligned box [lo, hi]^3 whose faces are n x n grids of quads (two triangles each),
/// outward, vertices shared: enough triangles for a tree with dipoles, faces exactly in the
/// coordinate planes.
engine::Mesh grid_box(float lo, float hi, int n);

/// Every triangle's corners in reverse order (inside out), or twice (each triangle repeated).
engine::Mesh flipped(const engine::Mesh& m);
engine::Mesh doubled(const engine::Mesh& m);
/// `m` without the triangles whose number k has (k * 2654435761 + seed) % 1000 < permille: a fixed
/// pseudo-random `permille`/1000 share removed (holes).
engine::Mesh without_faces(const engine::Mesh& m, unsigned permille, std::uint32_t seed);
/// `m` moved by `offset` and scaled by `scale` about the origin (scale first).
engine::Mesh moved(const engine::Mesh& m, float scale, accel::Vec3f offset);
/// Sliver triangles (one corner 1e-6 of the edge's length off the midpoint of the opposite edge,
/// and needles with two corners 1e-7 apart) around a small icosphere.
engine::Mesh slivers();

/// The largest |tree - oracle| over `points` and the largest excess of |tree - exact| over the
/// tree's own bound (<= 0 when the bound holds), evaluated with `beta`.
struct TreeCheck {
    double worst_vs_oracle = 0.0;
    double worst_bound_excess = -1.0;
    double largest_bound = 0.0;  ///< > 0 when some point used a dipole
};
/// The exact sum (make_exact_winding) and the oracle at each point, to check many trees against.
struct Reference {
    std::vector<double> exact, oracle;
};
Reference reference(const accel::TriangleView& tris, const std::vector<accel::Vec3f>& points);
TreeCheck check_tree(const accel::WindingTree& tree, const Reference& ref, const std::vector<accel::Vec3f>& points,
                     double beta);
TreeCheck check_tree(const accel::WindingTree& tree, const accel::TriangleView& tris,
                     const std::vector<accel::Vec3f>& points, double beta);

}  // namespace arbor::testing
