#pragma once
/// Helpers of the tests of the queries beyond closest and any hit (all hits, closest point,
/// inside): every structure and layout that answers them, query points of every stiff kind, the
/// double-precision winding number, and collecting all hits.
#include "accel/interface/accel.h"
#include "accel/structures/wide_paths.h"
#include "engine/mesh.h"
#include "testing.h"

#include <memory>
#include <string>
#include <vector>

namespace arbor::testing {

struct NamedAccel {
    std::string name;  ///< "bvh-sah/w16", "bvh-sah/scalar", "kdtree", ...
    std::unique_ptr<accel::Accel> accel;
};

/// brute, kdtree and each BVH (bvh-median, bvh-sah, lbvh) on its SIMD layout at every width this
/// build has (`every_width`) or at the default width only, and on its scalar layout.
std::vector<NamedAccel> query_structures(const accel::TriangleView& v, bool every_width);

/// Query points for closest-point tests, about `n` of each kind: on the surface (random points of
/// random triangles), at vertices, on edges (midpoints and ends), inside the box grown by 10%, and
/// far away (up to 1000 box diagonals). Deterministic for a seed.
std::vector<accel::Vec3f> query_points(const engine::Mesh& m, std::size_t n, std::uint32_t seed);

/// The generalised winding number of the mesh around p (sum of solid angles / 4 pi), in double:
/// an integer for a point off a closed surface (1 inside a simple closed surface, 0 outside).
double winding_number(const engine::Mesh& m, const accel::Vec3f& p);

/// All hits of every ray (Accel::trace_all), as lists.
std::vector<std::vector<accel::Hit>> all_hits(const accel::Accel& a, const std::vector<accel::Ray>& rays);

/// Whole records equal bit for bit (t, prim, u, v).
bool same_hit(const accel::Hit& a, const accel::Hit& b);
bool same_point(const accel::PointHit& a, const accel::PointHit& b);

}  // namespace arbor::testing
