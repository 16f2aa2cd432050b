#pragma once
/// WindingTree: what answers generalized winding numbers for a structure (solid_angle.h), made on
/// the first winding query (Accel::make_winding_tree), never by a plain build. Two kinds exist: the
/// exact sum over every triangle (make_exact_winding, below) and the hierarchical one over a BVH
/// layout with a dipole per child box (winding_walk.h; bvh/bvh2_winding.h, wide/wide_winding.h).
#include "accel/core/geometry.h"

#include <memory>
#include <span>
#include <string_view>

namespace arbor::accel {

/// The accuracy of a hierarchical evaluation: a cluster (a child box's triangles) is replaced by
/// its dipole when the point is farther than beta times the cluster's radius from its centroid.
/// beta > 1; +inf evaluates every triangle (exact). 2 is libigl's default.
inline constexpr double default_winding_beta = 2.0;

class WindingTree {
public:
    virtual ~WindingTree() = default;

    /// out[i] = the winding number of the triangles around points[i] (a non-finite point: NaN).
    /// With a non-empty `bound`, bound[i] = a bound on |out[i] - the exact sum| (0 where every
    /// triangle was evaluated exactly; dipole_error_bound summed over the dipoles used). The
    /// answer for a point depends only on the point, the triangles and beta: not on the batch or
    /// the thread. Single-threaded: call from many threads on disjoint spans.
    virtual void winding_numbers(std::span<const Vec3f> points, double beta, std::span<double> out,
                                 std::span<double> bound = {}) const = 0;
    /// What answers: "exact", "bvh2" (the scalar layout), "wide<N>" (the SIMD layout), each with
    /// " (internal)" when the tree was built for the winding numbers only.
    virtual std::string_view method() const = 0;
    /// Bytes of the data made for the winding numbers (dipoles; an internal tree's layout too).
    virtual std::size_t memory_bytes() const = 0;
    /// Milliseconds it took to make (dipoles; an internal tree's build too).
    double build_ms() const { return build_ms_; }

protected:
    double build_ms_ = 0.0;
};

/// The exact winding numbers of `tris` (which must outlive the tree): every finite triangle's
/// solid angle, summed in double in triangle order, whatever beta (a triangle with a NaN or
/// infinite corner is left out, as every structure leaves it out). Builds nothing.
std::unique_ptr<WindingTree> make_exact_winding(const TriangleView& tris);

}  // namespace arbor::accel
