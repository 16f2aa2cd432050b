#pragma once
/// The stiff cases: meshes and rays, independent of any acceleration structure, shared by the
/// doctest suite (small sizes) and `arbor stress` (full sizes). Each case is judged by the
/// double-precision oracle (oracle.h) plus the promises its rays carry (RayTag).
#include "accel/core/ray.h"
#include "engine/mesh.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace arbor::stress {

using accel::Vec3f;

/// What a ray promises beyond the oracle's verdict.
struct RayTag {
    /// A secondary ray leaving triangle `source_prim` (offset_ray.h): hitting that triangle again
    /// is a double hit (a self-intersection).
    std::uint32_t source_prim = accel::invalid_prim;
    /// From inside a closed mesh: the ray must hit (a miss is a false miss even in the band), at
    /// a t no larger than surface_t (it aims at a point of the surface; +inf: anywhere). A hit
    /// behind it leaked through the surface. NaN: no promise.
    float surface_t = std::numeric_limits<float>::quiet_NaN();
    /// Starts just past the ray's crossing of a closed surface: a hit the oracle rejects is a
    /// double hit (the same crossing hit twice at different t).
    bool continuation = false;
    /// The parity of the closed surfaces' crossings in [tnear, tfar] (Accel::trace_all): 1 odd
    /// (from inside), 0 even, -1 no promise. A wrong parity is a crossing counted twice (a double
    /// hit, e.g. an edge or vertex given to two triangles) or lost (a false miss).
    int parity = -1;

    bool must_hit() const { return !std::isnan(surface_t); }
};

struct StressCase {
    std::string name;  ///< row name in the stress table
    std::string what;  ///< one line: what the case stresses
    engine::Mesh mesh;
    std::vector<accel::Ray> rays;
    std::vector<RayTag> tags;  ///< one per ray
    /// Triangles [0, parity_prims) form the closed surfaces that RayTag::parity counts the
    /// crossings of; later ones (open scenery around them) are not counted.
    std::size_t parity_prims = std::numeric_limits<std::size_t>::max();
    /// Triangles every structure must drop as non-finite (-1: not checked).
    std::int64_t expected_dropped = -1;

    void add(const accel::Ray& r, const RayTag& tag = {}) {
        rays.push_back(r);
        tags.push_back(tag);
    }
};

/// `small`: the doctest sizes (cheap under the sanitizers); `full`: `arbor stress`.
enum class Size { small, full };

/// Every built-in case, in table order.
std::vector<StressCase> make_stress_cases(Size size);

/// Watertightness on a closed mesh given by the caller (e.g. a model file): rays from interior
/// points (found by the oracle's crossing parity) aimed exactly at vertices and at points on
/// edges, each followed by its continuation. Throws std::invalid_argument when `mesh` is not
/// closed (every edge shared by exactly two triangles, opposite orientation) or no interior point
/// is found.
StressCase make_closed_model_case(const engine::Mesh& mesh, const std::string& name, Size size);

/// True when every directed edge of `mesh` appears once and its reverse once (closed, oriented).
bool is_closed(const engine::Mesh& mesh);

// The generators, one per family (cases_*.cpp).
void add_closed_cases(std::vector<StressCase>& out, Size size);
void add_grid_cases(std::vector<StressCase>& out, Size size);
void add_precision_cases(std::vector<StressCase>& out, Size size);
void add_degenerate_cases(std::vector<StressCase>& out, Size size);
void add_ray_cases(std::vector<StressCase>& out, Size size);
void add_in_plane_cases(std::vector<StressCase>& out, Size size);

/// Rays from `origin` (inside the closed mesh c.mesh) aimed exactly at every vertex and at points
/// on every edge (the midpoint and the points 1/8 and 5/8 along it), each with its continuation
/// (tnear just past the target, tagged). All must hit. With `star` the mesh is star-shaped around
/// `origin` (every segment from it to the surface crosses the surface once, at its end), so the
/// hit must also come no later than the target; otherwise a line through a vertex may only touch
/// the surface there and cross it later. `stride` > 1 keeps every stride-th vertex and edge.
void add_rays_at_vertices_and_edges(StressCase& c, const Vec3f& origin, bool star, std::size_t stride = 1);

}  // namespace arbor::stress
