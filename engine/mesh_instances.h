#pragma once
/// Instances in an engine scene: parts of the scene's one Mesh (ranges of its triangles) placed
/// any number of times by affine transforms (accel/instances/affine.h), so that a file or a
/// built-in scene that repeats a model costs the model once plus a transform per copy.
///
/// The Mesh keeps every attribute (materials, normals, texture coordinates, colours) once, so the
/// renderer's plan and shading read it as they read any mesh; only positions and normals are
/// carried to the world per hit. Triangles [0, drawn) of the mesh are placed as they are; the
/// parts follow them, each placed only by its instances.
///
/// Triangles are numbered as the flattened scene numbers them: first the `drawn` triangles, then
/// instance by instance (in id order) its part's triangles in mesh order. This is the numbering
/// of accel::InstanceAccel over the placements make_instanced_accel makes, and of flatten().
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "accel/instances/affine.h"
#include "accel/interface/accel.h"
#include "engine/mesh.h"

namespace arbor::engine {

/// Triangles [first, first + count) of the mesh: one placeable model. `vertices`, `normals` and
/// `uvs` count the entries of those arrays the part holds (for counts as a flattened copy, which
/// repeats them per placement, gives them).
struct MeshPart {
    std::uint32_t first = 0, count = 0;
    std::uint32_t vertices = 0, normals = 0, uvs = 0;
};

/// One placement of a part.
struct PartInstance {
    std::uint32_t part = 0;
    accel::Affine transform;  ///< object (mesh) coordinates -> world
};

/// A hit's triangle as the mesh holds it: its number in the mesh and the transform that places
/// it (null: placed as it is).
struct PlacedPrim {
    std::uint32_t prim = 0;
    const accel::Affine* to_world = nullptr;
};

struct MeshInstances {
    std::vector<MeshPart> parts;          ///< ascending, disjoint, after the drawn triangles
    std::vector<PartInstance> instances;  ///< in id order
    std::uint32_t drawn = 0;              ///< triangles [0, drawn) are placed as they are
    std::vector<std::uint64_t> first;     ///< per instance, its first global triangle number (index())

    bool empty() const { return instances.empty(); }
    /// Checks the parts and instances against `mesh` and numbers the instances' triangles;
    /// InputError naming `name` for a part outside the mesh or out of order, an unknown part, a
    /// transform check_affine refuses, or 2^32 - 1 placed triangles or more.
    void index(const Mesh& mesh, const std::string& name);
    /// Triangles placed: the drawn ones plus every instance's part (what a flattened copy holds).
    std::uint64_t effective_triangles() const;
    /// Entries of a per-part array (`MeshPart::vertices`, `normals` or `uvs`) a flattened copy
    /// holds, of `held` in the mesh: those outside the parts once, each part's once per instance.
    std::uint64_t effective(std::uint64_t held, std::uint32_t MeshPart::*field) const;
    /// The mesh triangle and transform of global triangle number `global` (after index()).
    PlacedPrim locate(std::uint32_t global) const;
};

/// The world box of the scene's placed triangles; mesh.bounds when there are no instances.
/// `exact`: every used vertex carried over as flatten() carries it (time grows with the placed
/// vertices); otherwise the parts' boxes carried over (a box around the exact one, at a cost
/// that grows with the instances).
accel::Bounds world_bounds(const Mesh& mesh, const MeshInstances& inst, bool exact = false);

/// The flattened mesh: every placed triangle with its vertices carried to the world (in double,
/// rounded to float once), normals by the inverse transpose, the other attributes as they are,
/// numbered as above. For tests, and for the commands that do not trace instances.
Mesh flatten(const Mesh& mesh, const MeshInstances& inst);
/// Bytes flatten() would allocate, about.
std::uint64_t flatten_bytes(const Mesh& mesh, const MeshInstances& inst);

/// The two-level structure (accel/instances/instance_accel.h): one structure of `kind` per part
/// (and one over the drawn triangles), a top BVH over the placements. `kind` automatic: bvh-sah.
std::unique_ptr<accel::Accel> make_instanced_accel(const Mesh& mesh, const MeshInstances& inst, accel::AccelKind kind,
                                                   const accel::BuildConfig& cfg);

}  // namespace arbor::engine
