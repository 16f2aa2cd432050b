#pragma once
/// What `--accel auto` knows about a job before it builds anything: the shape of the scene (from
/// the vertex arrays and a strided sample of triangles) and of the rays (their count, query and
/// coherence). The cost model (auto_model.h) predicts build and trace times from these numbers
/// alone; the benchmark records them beside its timings so that the model can be fitted from its
/// output (perf/model/fit_auto_model.py). Everything here is cheap (tens of microseconds on a
/// 100k-triangle scene) and deterministic.
#include "accel/core/geometry.h"
#include "accel/core/query.h"

#include <span>

namespace arbor::accel {

/// The scene's shape. All ratios are dimensionless, so a scene and a scaled copy have one shape.
struct SceneShape {
    std::size_t triangles = 0;
    /// Bounds of the finite vertices (unreferenced ones included: the loader keeps none).
    Bounds bounds;
    /// triangles x mean surface area of a triangle's box / surface area of the scene's box: about
    /// how many triangle boxes a ray through the scene meets. About 1-10 for a closed model; large
    /// for scenes of big overlapping triangles (halls with braces spanning the room, soups).
    double overlap = 0.0;
    /// scene diagonal / (median triangle box diagonal x sqrt(triangles)): near 1 for a model whose
    /// triangles tile its surface evenly; large when a small dense model sits in a big room.
    double spread = 0.0;
    /// mean / median triangle box diagonal: big triangles among small ones.
    double size_tail = 0.0;
    /// median of (triangle box diagonal^2 / twice the triangle's area): 1-3 for well-shaped
    /// triangles, large for long thin ones (grass blades).
    double thinness = 0.0;
    /// Triangles of the sample.
    std::size_t sampled = 0;
};

/// The shape of `tris` from at most `sample` triangles spread evenly over the numbering (all of
/// them when there are fewer). Non-finite and zero-area triangles are left out of the ratios.
SceneShape scene_shape(const TriangleView& tris, std::size_t sample = 4096);

/// The shape of one group of rays of a job: how many, which query, how coherent.
struct RayShape {
    double rays = 0.0;  ///< rays the job traces in this group
    Query query = Query::closest;
    /// coherence.h's fractions over 16-ray groups: one direction octant and origins within 5% of the
    /// scene's diagonal (`coherent`), origins within 5% whatever the octants (`together`).
    /// Negative: not known (pick_accel measures its sample, or takes 0 without one).
    double coherent = -1.0, together = -1.0;
    /// The path the job will run these rays on, when the caller decides it (the renderer: packets
    /// for camera and shadow rays, single rays for bounces); `best`: auto picks it.
    TracePath path = TracePath::best;
    /// What the caller knows of the rays' coherence instead (the renderer's batches): the path
    /// policy then picks the path per structure (path_policy.h, rules 4-5).
    RayHint hint = RayHint::unknown;
};

/// The shape of `rays` (a sample of what will be traced; at most 64 groups of 16 are looked at),
/// standing for `count` rays of query `query` in a scene of diagonal `scene_diagonal`.
RayShape ray_shape(std::span<const Ray> rays, double count, Query query, float scene_diagonal);

}  // namespace arbor::accel
