#pragma once
/// What a public arbor::Scene holds (private to the library): every mesh concatenated into one
/// engine::Mesh (geometry g owns triangles [first_prim[g], first_prim[g + 1])), the structure built
/// over it, and the task arena its batches run in. Also the one place internal exceptions become
/// arbor::Error.
#include <arbor/arbor.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "accel/instances/affine.h"
#include "accel/interface/accel.h"
#include "engine/mesh.h"

namespace arbor::accel {
class InstanceAccel;
}

namespace arbor {

class CallArena;  // api/batch.h

struct Scene::Impl {
    engine::Mesh mesh;
    std::vector<std::uint32_t> first_prim;  ///< per geometry, its first triangle in `mesh`
    std::vector<std::uint32_t> first_vertex;  ///< per geometry, its first vertex in `mesh`
    accel::Bounds bounds;                   ///< of the finite triangles
    BuildOptions options;                   ///< of the last build (a lazy build uses the defaults)
    std::unique_ptr<accel::Accel> accel;
    std::string accel_name, accel_reason;
    std::vector<std::string> load_warnings;  ///< from Scene::load
    std::unique_ptr<tbb::task_arena> arena;
    int threads = 0;  ///< the arena's threads: build's `threads` as usable_threads() takes it (0 = all)
    std::atomic<bool> ready{false};
    /// For update_vertices (api/update.cpp): the last build's wall time (what a rebuild is expected
    /// to take), the SAH ratio of the tree in use (1 after a build, RefitResult::ratio after a
    /// refit), the rays (and points) answered and the nanoseconds spent answering them since the
    /// last build or update, and what the last update did and why.
    double build_ms = 0.0;
    double sah_ratio = 1.0;
    mutable std::atomic<std::uint64_t> answered{0}, answer_ns{0};
    std::string update_action, update_reason;
    std::mutex build_mutex;
    /// Made on demand, dropped by add_mesh and build (winding.cpp): the structure's winding-number
    /// tree (it may read the structure's layout), made by the first winding query, and closed()'s
    /// answer (-1: not known yet).
    std::unique_ptr<accel::WindingTree> winding;
    std::atomic<bool> winding_ready{false};
    std::atomic<int> closed_state{-1};
    std::mutex lazy_mutex;
    /// Instances (api/instances.cpp): the mesh each places and its transform, by instance id.
    struct Instance {
        std::uint32_t geom;
        accel::Affine transform;
    };
    std::vector<Instance> instances;
    /// The two-level structure when the scene holds instances (then `accel` is it), else null.
    const accel::InstanceAccel* placed = nullptr;

    /// Builds the two-level structure (api/instances.cpp): one structure of `kind` per mesh.
    void build_instanced(accel::AccelKind kind, const accel::BuildConfig& cfg);
    /// The scene's world box: `bounds`, or with instances the box of their placements.
    accel::Bounds world_bounds() const;
    /// Geometry id, triangle number and instance id of a global triangle number of `placed`.
    void locate_placed(std::uint32_t global, std::uint32_t& geom, std::uint32_t& prim, std::uint32_t& inst) const;

    /// The structure, built with the last options first when it is not (thread-safe).
    const accel::Accel& structure();
    void build_locked(const BuildOptions& o);
    /// The structure's winding tree, made first (on the call's threads) when it is not (thread-safe).
    const accel::WindingTree& winding_tree(CallArena& call);
    /// Forgets what was made on demand (before the structure or the mesh changes).
    void drop_derived() {
        winding_ready = false;
        winding.reset();
        closed_state = -1;
    }

    /// Geometry id and triangle number within it of triangle `global` of `mesh`.
    void locate(std::uint32_t global, std::uint32_t& geom, std::uint32_t& prim) const {
        std::uint32_t inst;
        locate(global, geom, prim, inst);
    }
    /// The same and the instance that placed it (invalid_id for none).
    void locate(std::uint32_t global, std::uint32_t& geom, std::uint32_t& prim, std::uint32_t& inst) const {
        inst = invalid_id;
        if (global == accel::invalid_prim) {
            geom = prim = invalid_id;
            return;
        }
        if (placed) return locate_placed(global, geom, prim, inst);
        std::size_t g = 0;
        if (first_prim.size() > 1) {
            std::size_t lo = 0, hi = first_prim.size();  // the last g with first_prim[g] <= global
            while (hi - lo > 1) {
                const std::size_t mid = (lo + hi) / 2;
                (first_prim[mid] <= global ? lo : hi) = mid;
            }
            g = lo;
        }
        geom = std::uint32_t(g);
        prim = global - first_prim[g];
    }

    Hit to_public(const accel::Hit& h) const {
        Hit out;
        if (!h.is_hit()) return out;
        locate(h.prim, out.geom, out.prim, out.inst);
        out.t = h.t, out.u = h.u, out.v = h.v;
        return out;
    }
};

/// A thread count as arbor uses it: 0 stays 0 (all cores), and a count above the machine's cores
/// (as oneTBB counts them, affinity mask included) is taken as all cores, so that oneTBB never
/// prints its warning that a request for more workers was ignored.
inline int usable_threads(int requested) { return std::min(requested, tbb::info::default_concurrency()); }

/// Runs f, turning every internal exception into arbor::Error.
template <class F> decltype(auto) guarded(F&& f);
[[noreturn]] void rethrow_as_error();

template <class F> decltype(auto) guarded(F&& f) {
    try {
        return f();
    } catch (...) {
        rethrow_as_error();
    }
}

}  // namespace arbor
