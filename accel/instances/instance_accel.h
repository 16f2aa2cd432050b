#pragma once
/// A two-level scene as one Accel: meshes, each with its own bottom structure (any kind, built
/// once however often the mesh is placed), placed by affine transforms (affine.h) under a top BVH
/// over the placements' world boxes (top_bvh.h).
///
/// Triangles are numbered globally, placement by placement: placement k's triangle j is
/// first(k) + j, so a Hit's prim says both which placement and which triangle, and the one tie
/// rule (smallest t, then lowest number; core/hit_record.h) holds across placements as within one.
///
/// Rays are carried into each placement's object space in double and rounded to float once: the
/// origin by the inverse transform, the direction by the inverse of its 3x3 part, unnormalized,
/// so that t along the object ray is the world t and tnear, tfar and the hits' t need no
/// conversion. An identity placement gets the ray untouched (its hits are those of the mesh on its
/// own, bit for bit). Within a placement the watertight guarantee of the bottom structure holds.
/// Between placements, which can meet only along open edges of their meshes, the triangles around
/// those edges (seams.h) are also tested in world space with the caller's ray, against corners
/// rounded as a flattened scene rounds them (tests/test_instance_edges.cpp, docs/cpp-api.md).
#include "accel/instances/affine.h"
#include "accel/instances/seams.h"
#include "accel/instances/top_bvh.h"
#include "accel/interface/accel.h"

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace arbor::accel {

/// One mesh's own copy of its triangles (vertex numbers from 0), kept for the bottom structure and
/// the closest-point queries.
struct InstanceMesh {
    std::vector<float> x, y, z;
    std::vector<std::uint32_t> indices;
    Bounds bounds;  ///< of its finite triangles

    TriangleView view() const { return {x, y, z, indices}; }
};

/// A mesh and its bottom structure.
struct Bottom {
    std::unique_ptr<InstanceMesh> mesh;  ///< held by pointer: the structure may keep views into it
    std::unique_ptr<Accel> accel;
};

/// One placement of a mesh.
struct Placement {
    std::uint32_t geom = 0;  ///< the mesh (index into the bottoms)
    std::uint32_t id = 0;    ///< the caller's name for it (an instance id), for messages
    Affine to_world, to_object;
    bool identity = true;
    std::uint32_t first = 0;  ///< global number of its triangle 0

    /// A placement of `geom` by `t` (which check_affine accepted).
    static Placement make(std::uint32_t geom, std::uint32_t id, const Affine& t) {
        Placement p;
        p.geom = geom, p.id = id, p.to_world = t, p.to_object = t.inverse(), p.identity = t.is_identity();
        return p;
    }
};

class InstanceAccel final : public Accel {
public:
    /// The scene of `placements` (their `first` is assigned here, in order) of `bottoms` (indexed
    /// by Placement::geom; a bottom no placement names may be empty). `kind` is reported as the
    /// structure's kind (the bottoms' kind). Throws std::length_error when the placed triangles
    /// number 2^32 - 1 or more (the global numbers would not fit).
    InstanceAccel(AccelKind kind, std::vector<Bottom> bottoms, std::vector<Placement> placements);

    void trace_all(std::span<const Ray> rays, HitSink& sink) const override;
    /// Nearest points in world distance: similarity placements through their bottom structure
    /// (the object-space nearest is the world nearest, then measured in world space); other
    /// placements (non-uniform scale, shear) by an exact world-space scan of their triangles.
    void closest_points(std::span<const Vec3f> points, float max_distance, std::span<PointHit> out) const override;

    std::span<const Placement> placements() const { return placements_; }
    const Bottom& bottom(std::uint32_t geom) const { return bottoms_[geom]; }
    /// World box of every placement.
    const Bounds& bounds() const { return bounds_; }
    /// The placement of global triangle number `prim`.
    std::size_t placement_of(std::uint32_t prim) const;
    /// Bytes of the top level (nodes, placements) and of the bottoms' structures.
    std::size_t top_bytes() const;
    std::size_t bottom_bytes() const;
    /// Bytes of the placements' world-space seam triangles and their structures.
    std::size_t seam_bytes() const;
    /// Meshes with at most this many seam triangles, or an eighth of their triangles, have their
    /// seams placed in world space; larger seams are left to the object-space test.
    static constexpr std::size_t seam_limit = 64;

protected:
    void run(std::span<const Ray> rays, std::span<Hit> hits, Query query, TracePath path,
             TraceCounters* counters) const override;

private:
    /// The (placement, ray) pairs of a batch whose world boxes the rays meet, grouped by placement
    /// (ray order kept within each group): group k is order[start[k] .. start[k + 1]). `visit`
    /// lists the placements met, nearest first by their rays' mean entry distance (closest-hit
    /// rays then meet near hits first and test less of what lies behind).
    struct Groups {
        std::vector<std::uint32_t> start, order, visit;
        std::vector<double> enter;  ///< beside `order`: where the ray enters the placement's box
    };
    void group(std::span<const Ray> rays, Groups& g) const;
    Ray to_object(const Placement& p, const Ray& r) const;
    void nearest_in(const Placement& p, const Vec3f& point, double& best2, PointHit& best) const;

    /// Per placement that is not the identity and whose mesh has seams: the seam triangles in
    /// world space (3 corners each, in the order of SeamSet::tris) and a structure over them.
    struct WorldSeams {
        std::unique_ptr<InstanceMesh> mesh;
        std::unique_ptr<Accel> accel;
    };
    WorldSeams world_seams(const Placement& p) const;
    /// The world rays of group [b, e) of `g` (closest hits: up to their best hit so far), the seam
    /// structure's answers merged into `hits` with the mesh's global triangle numbers.
    void trace_seams(std::size_t k, std::span<const Ray> rays, std::span<Hit> hits, const Groups& g,
                     const TraceRequest& req) const;

    std::vector<Bottom> bottoms_;
    std::vector<SeamSet> seams_;       ///< per mesh
    std::vector<WorldSeams> placed_seams_;  ///< per placement
    std::vector<Placement> placements_;
    std::vector<double> scale_;  ///< per placement: its uniform scale, or 0 for the scan
    TopBvh top_;
    Bounds bounds_;
};

}  // namespace arbor::accel
