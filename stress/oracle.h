#pragma once
/// The double-precision oracle of the stiff-case suite. It decides, for a float ray and a float
/// triangle exactly as stored, whether the ray meets the triangle within [tnear, tfar], and says
/// when float arithmetic cannot decide it: a ray whose float-rounded position in the watertight
/// test's sheared frame (Woop, Benthin, Wald 2013) may lie on either side of an edge, a hit whose t
/// may lie on either side of tnear/tfar, a triangle seen edge-on, or a result beyond float range.
/// Those rays form the "band": any answer float arithmetic could give is accepted there, and the
/// band is counted, never hidden.
///
/// Error model (unit roundoff u = 2^-24): a float implementation computes each sheared vertex
/// coordinate (v - o)[k] - s_k (v - o)[kz] with an absolute error below K u |v - o|_inf (K = 16 is
/// four times the error of the scalar test), except when the ray is parallel to an axis and the
/// differences v - o are floats: then those coordinates are exact. The edge functions' errors
/// follow from the coordinates' errors; their signs are exact for exact coordinates (the float
/// test refines zeros in double), so integer grids traced along the axes have no band at all.
/// There an exactly zero edge function (a ray exactly through an edge or vertex) gets the sign the
/// triangle test's tie rule gives it (simd/ray_triangle.h), worked out here from its definition.
#include "accel/core/geometry.h"

#include <cstdint>
#include <span>
#include <vector>

namespace arbor::stress {

using accel::Hit;
using accel::Ray;
using accel::Vec3f;

/// The verdict on one (ray, triangle) pair.
struct TriVerdict {
    enum Kind : std::uint8_t { miss, hit, unsure } kind = miss;
    double t = 0.0;    ///< the exact t of the ray's crossing of the triangle's plane (hit or unsure)
    double tol = 0.0;  ///< how far a float implementation's t may lie from `t`
};

/// The oracle's answer for one ray over all triangles.
struct OracleAnswer {
    bool traceable = false;  ///< accel::ray_is_traceable: an untraceable ray must miss
    double t_hit = 0.0;      ///< nearest certain hit (+inf when no triangle is certainly hit)
    double t_hit_tol = 0.0;
    std::uint32_t prim = accel::invalid_prim;  ///< triangle of t_hit
    /// In the band: some unsure triangle could change the closest or the any-hit answer (it may be
    /// hit at or before t_hit, or it may be the only hit there is).
    bool band = false;
    bool certain_hit() const { return prim != accel::invalid_prim; }
};

class Oracle {
public:
    /// Keeps a copy of the finite triangles of `tris` (non-finite ones are never hit).
    explicit Oracle(const accel::TriangleView& tris);

    /// The verdict on triangle `prim` (a miss when the ray is not traceable or the triangle is
    /// non-finite).
    TriVerdict classify(const Ray& ray, std::uint32_t prim) const;
    /// The answer over all triangles (one thread; see answers()).
    OracleAnswer answer(const Ray& ray) const;
    /// answer() for every ray, in parallel (tbb::parallel_for), deterministic.
    std::vector<OracleAnswer> answers(std::span<const Ray> rays) const;
    /// How many triangles the ray certainly hits in [tnear, tfar], or -1 when any is unsure
    /// (for crossing-parity inside tests).
    int crossings(const Ray& ray) const;

    /// Finite triangles kept.
    std::size_t size() const { return prims_.size(); }

private:
    struct Tri {
        Vec3f v[3];
        double cx, cy, cz, radius;  ///< bounding sphere, for a conservative cull
    };
    std::vector<Tri> tris_;             ///< finite triangles only
    std::vector<std::uint32_t> prims_;  ///< their triangle numbers
    std::vector<std::int64_t> slot_;    ///< triangle number -> index in tris_, or -1
};

}  // namespace arbor::stress
