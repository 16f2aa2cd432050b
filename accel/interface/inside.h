#pragma once
/// Inside or outside a closed surface, by the parity of a ray's crossings (Accel::trace_all).
///
/// With the watertight test, a ray from a point crossing a closed mesh is counted exactly: where
/// two triangles share an edge the ray's side of it is decided once, with the same arithmetic, for
/// both (Woop, Benthin, Wald 2013), and a ray exactly through an edge or a vertex is given to one
/// triangle there by the test's tie rule (simd/ray_triangle.h). What the parity cannot decide is a
/// point on the surface itself (a crossing at t ~ 0 may be counted or not), and an edge or vertex
/// of a mesh that is not closed and consistently oriented. Those rays are "in the band":
/// a hit with a barycentric within band_bary of 0, or within band_t of the point. Then the next of
/// a fixed set of directions is tried; when every direction is in the band (a point on the surface),
/// the majority of their parities answers.
#include "accel/interface/accel.h"

#include <cstdint>
#include <span>

namespace arbor::accel {

struct InsideConfig {
    /// Directions tried per point at most (the first that is out of the band decides).
    int max_directions = 8;
    /// A hit whose u, v or 1 - u - v is at most this is in the band (an exact 0 is what breaks the
    /// count; a little more costs only a second ray now and then).
    float band_bary = 0x1p-20f;
    /// A hit at a distance at most this times the scene's coordinate scale (the largest |coordinate|
    /// or extent of the scene box and the point) is in the band: the point lies on the surface.
    float band_t = 0x1p-18f;
    /// The unit directions tried in turn; empty: inside_directions(). (Tests pass axis-parallel
    /// ones, whose exact arithmetic meets edges exactly.)
    std::span<const Vec3f> directions;
};

/// The unit directions tried in turn (none parallel to an axis or a diagonal; fixed, so answers
/// are deterministic).
std::span<const Vec3f> inside_directions();

/// out[i] = 1 when points[i] is inside the closed surfaces of `accel` (odd crossing parity), else
/// 0. `scene` is the scene's box (the band's scale). Non-finite points are outside. Single-threaded;
/// call from many threads on disjoint spans.
void inside_points(const Accel& accel, const Bounds& scene, std::span<const Vec3f> points, std::span<std::uint8_t> out,
                   const InsideConfig& cfg = {});

}  // namespace arbor::accel
