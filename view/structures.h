#pragma once
/// The structures the viewer's sessions trace: built on first use, shared by the sessions that use
/// the same one, freed when none does. The cost integrator needs the structure's counting layout
/// (the scalar reference walk) beside the SIMD one; the other integrators get what `arbor render`
/// builds (the SIMD layouts only), so their frames match its frames.
#include <map>
#include <memory>
#include <mutex>

#include "accel/interface/accel.h"
#include "engine/mesh_instances.h"

namespace arbor::view {

class StructureCache {
public:
    /// The mesh `tris` views must outlive the cache; `base` is the command line's build settings.
    StructureCache(const accel::TriangleView& tris, const accel::BuildConfig& base) : tris_(tris), base_(base) {}
    /// A scene of instances (engine/mesh_instances.h): the two-level structure, its placed
    /// meshes of each kind. `mesh` and `placed` must outlive the cache.
    StructureCache(const engine::Mesh& mesh, const engine::MeshInstances& placed, const accel::BuildConfig& base)
        : tris_(mesh.view()), base_(base), mesh_(&mesh), placed_(placed.empty() ? nullptr : &placed) {}

    struct Entry {
        std::shared_ptr<const accel::Accel> accel;
        double build_ms = 0;  ///< the build's time (also when another session built it)
        bool shared = false;  ///< another session had built it already
    };
    /// The structure of `kind`, with the counting layout when `counting`: a live one, or built on
    /// the calling thread (in its TBB arena) while other callers wait.
    Entry get(accel::AccelKind kind, bool counting);

private:
    accel::TriangleView tris_;
    accel::BuildConfig base_;
    const engine::Mesh* mesh_ = nullptr;
    const engine::MeshInstances* placed_ = nullptr;
    std::mutex mutex_;
    struct Slot {
        std::weak_ptr<const accel::Accel> accel;
        double build_ms = 0;
    };
    std::map<std::pair<accel::AccelKind, bool>, Slot> slots_;
};

}  // namespace arbor::view
