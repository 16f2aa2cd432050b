/// arbor::Scene: its meshes, loading, building (auto resolved here), and the error boundary.
#include "api/scene_impl.h"

#include "accel/factory/make_accel.h"
#include "accel/select/auto_select.h"
#include "accel/dispatch/kernel_set.h"
#include "accel/factory/memory_estimate.h"
#include "engine/error.h"
#include "engine/mesh_loader.h"
#include "engine/rayfile.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>

namespace arbor {

Error::Error(Kind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}

std::string version() { return ARBOR_VERSION; }
std::string kernel_set() { return std::string(accel::kernel_set()); }

void rethrow_as_error() {
    try {
        throw;
    } catch (const Error&) {
        throw;
    } catch (const accel::MemoryLimitError& e) {
        throw Error(Error::Kind::out_of_memory, std::string("max_memory: ") + e.what());
    } catch (const engine::InputError& e) {
        throw Error(Error::Kind::bad_file, e.what());
    } catch (const std::bad_alloc&) {
        throw Error(Error::Kind::out_of_memory, "out of memory");
    } catch (const std::exception& e) {
        throw Error(Error::Kind::invalid_argument, e.what());
    }
}

Scene::Scene() : impl_(std::make_unique<Impl>()) {}
Scene::~Scene() = default;
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;

namespace {
/// Unreadable files are Error::Kind::io with the command line's message; the readers report
/// everything about the contents (Error::Kind::bad_file).
void check_readable(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw Error(Error::Kind::io, path + ": cannot open (is a directory)");
    if (!std::ifstream(path, std::ios::binary)) throw Error(Error::Kind::io, path + ": cannot open (" + std::strerror(errno) + ")");
}
}  // namespace

std::vector<Ray> read_rays(const std::string& path) {
    return guarded([&] {
        check_readable(path);
        const std::vector<accel::Ray> in = engine::read_rays(path);
        static_assert(sizeof(Ray) == sizeof(accel::Ray), "the record of rayfile.md");
        std::vector<Ray> out(in.size());
        if (!in.empty()) std::memcpy(static_cast<void*>(out.data()), in.data(), in.size() * sizeof(Ray));
        return out;
    });
}

Scene Scene::load(const std::string& path) {
    return guarded([&] {
        check_readable(path);
        engine::Warnings warnings;
        Scene s;
        // Every format `arbor info` reads (OBJ, PLY, STL, glTF); only the geometry is kept (the
        // queries need no materials, normals, texture coordinates or textures).
        engine::Mesh loaded = engine::load_mesh(path, warnings);
        engine::Mesh& m = s.impl_->mesh;
        m.x = std::move(loaded.x);
        m.y = std::move(loaded.y);
        m.z = std::move(loaded.z);
        m.indices = std::move(loaded.indices);
        m.bounds = loaded.bounds;
        s.impl_->first_prim.push_back(0);
        s.impl_->first_vertex.push_back(0);
        s.impl_->bounds = s.impl_->mesh.bounds;  // the loader refuses non-finite vertices
        s.impl_->load_warnings = std::move(warnings.lines);
        return s;
    });
}

std::uint32_t Scene::add_mesh(const float* positions, std::size_t vertex_count, std::size_t stride,
                              const std::uint32_t* indices, std::size_t triangle_count) {
    return guarded([&] {
        using Kind = Error::Kind;
        engine::Mesh& m = impl_->mesh;
        if (vertex_count != 0 && positions == nullptr) throw Error(Kind::invalid_argument, "add_mesh: positions is null");
        if (triangle_count != 0 && indices == nullptr) throw Error(Kind::invalid_argument, "add_mesh: indices is null");
        if (vertex_count != 0 && stride < 3 * sizeof(float))
            throw Error(Kind::invalid_argument, "add_mesh: stride " + std::to_string(stride) + " is below 12 bytes (x, y, z floats)");
        // Numbers the traversal reserves: a vertex or triangle count beyond 32 bits, or the miss id.
        constexpr std::size_t limit = 0xFFFFFFFFu;
        if (m.vertex_count() + vertex_count >= limit || m.triangle_count() + triangle_count >= limit)
            throw Error(Kind::invalid_argument, "add_mesh: the scene would hold 2^32 or more vertices or triangles");
        for (std::size_t t = 0; t < 3 * triangle_count; ++t)
            if (indices[t] >= vertex_count)
                throw Error(Kind::invalid_argument, "add_mesh: triangle " + std::to_string(t / 3) + " uses vertex " +
                                                        std::to_string(indices[t]) + ", but the mesh has " +
                                                        std::to_string(vertex_count) + " vertices");
        const auto base = std::uint32_t(m.vertex_count());
        const auto first = std::uint32_t(m.triangle_count());
        m.x.reserve(m.x.size() + vertex_count), m.y.reserve(m.y.size() + vertex_count), m.z.reserve(m.z.size() + vertex_count);
        const auto* bytes = reinterpret_cast<const unsigned char*>(positions);
        for (std::size_t i = 0; i < vertex_count; ++i) {
            float p[3];
            std::memcpy(p, bytes + i * stride, sizeof p);  // any stride, any alignment
            m.x.push_back(p[0]), m.y.push_back(p[1]), m.z.push_back(p[2]);
        }
        m.indices.reserve(m.indices.size() + 3 * triangle_count);
        for (std::size_t t = 0; t < 3 * triangle_count; ++t) m.indices.push_back(base + indices[t]);
        // The box of the finite triangles (the ones a structure keeps), grown by the new ones only.
        const accel::TriangleView view = m.view();
        for (std::size_t t = first; t < m.triangle_count(); ++t)
            if (view.triangle_is_finite(t)) impl_->bounds.grow(view.triangle_bounds(t));
        m.bounds = impl_->bounds;
        impl_->first_prim.push_back(first);
        impl_->first_vertex.push_back(base);
        // The structure no longer covers the scene: the next query builds again.
        impl_->drop_derived();
        impl_->ready = false;
        impl_->accel.reset();
        impl_->placed = nullptr;
        impl_->accel_name.clear(), impl_->accel_reason.clear();
        return std::uint32_t(impl_->first_prim.size() - 1);
    });
}

std::uint32_t Scene::add_mesh(const std::vector<float>& positions, const std::vector<std::uint32_t>& indices) {
    if (positions.size() % 3 != 0 || indices.size() % 3 != 0)
        throw Error(Error::Kind::invalid_argument, "add_mesh: positions and indices must hold whole triples (sizes " +
                                                       std::to_string(positions.size()) + " and " + std::to_string(indices.size()) + ")");
    return add_mesh(positions.data(), positions.size() / 3, 3 * sizeof(float), indices.data(), indices.size() / 3);
}

void Scene::Impl::build_locked(const BuildOptions& o) {
    using Kind = Error::Kind;
    const auto kind = accel::parse_accel_kind(o.accel);
    if (!kind)
        throw Error(Kind::invalid_argument, "build: unknown structure '" + o.accel + "' (expected " + accel::accel_kind_names() + ")");
    if (o.threads < 0) throw Error(Kind::invalid_argument, "build: threads must be >= 0 (0 = all cores), got " + std::to_string(o.threads));
    ready = false;
    drop_derived();  // the winding tree may read the structure's layout
    accel.reset();
    placed = nullptr;
    threads = usable_threads(o.threads);
    arena = std::make_unique<tbb::task_arena>(threads > 0 ? threads : int(tbb::task_arena::automatic));
    accel::BuildConfig cfg;
    cfg.max_memory = o.max_memory;
    cfg.layouts = accel::Layouts::simd;  // the layouts of the SIMD paths, as `arbor trace` builds them
    if (!instances.empty()) {
        build_instanced(*kind, cfg);
        options = o;
        ready = true;
        return;
    }
    cfg.compact = o.compact;  // (after the instances: their meshes are views the compact layout would outlive)
    const accel::TriangleView view = mesh.view();
    accel::AccelPick pick;
    arena->execute([&] {
        if (*kind == accel::AccelKind::automatic && mesh.triangle_count() == 0) {
            pick.kind = accel::AccelKind::bvh_sah;
            pick.reason = "the scene is empty";
        } else {
            // The command line's decision (accel::pick_accel, as `arbor trace --accel auto`) for
            // closest hits of 2^20 rays like those into the scene's bounds.
            pick = accel::pick_accel(*kind, accel::trace_job(view, {}, double(1 << 20), accel::Query::closest, accel::TracePath::best, cfg));
        }
        accel = pick.built ? std::move(pick.built) : accel::make_accel(pick.kind, view, cfg);
    });
    build_ms = accel->stats().build_ms;  // the structure's own build, without auto's decision
    sah_ratio = 1.0;
    answered = 0, answer_ns = 0;
    accel_name = std::string(accel::to_string(pick.kind));
    accel_reason = pick.reason;
    if (const std::string& why = accel->stats().compact_fallback; !why.empty())
        accel_reason += (accel_reason.empty() ? "" : "; ") + std::string("compact mode: ") + why;
    // pick.path is not kept: auto weighed its paths on a job it imagined (closest hits of rays it
    // had not seen), so each batch's own rays choose the path (api/queries.cpp, batch_request).
    options = o;
    ready = true;
}

const accel::Accel& Scene::Impl::structure() {
    if (!ready.load(std::memory_order_acquire)) {
        const std::lock_guard lock(build_mutex);
        if (!ready.load(std::memory_order_relaxed)) build_locked(options);
    }
    return *accel;
}

void Scene::build(const BuildOptions& options) {
    guarded([&] {
        const std::lock_guard lock(impl_->build_mutex);
        impl_->build_locked(options);
    });
}

bool Scene::built() const { return impl_->ready; }
std::string Scene::accel() const { return impl_->ready ? impl_->accel_name : std::string(); }
std::string Scene::accel_reason() const { return impl_->ready ? impl_->accel_reason : std::string(); }
std::vector<std::string> Scene::load_warnings() const { return impl_->load_warnings; }
std::size_t Scene::triangles() const { return impl_->mesh.triangle_count(); }
std::size_t Scene::meshes() const { return impl_->first_prim.size(); }

void Scene::bounds(float lo[3], float hi[3]) const {
    const accel::Bounds b = impl_->world_bounds();
    for (int k = 0; k < 3; ++k) lo[k] = b.lo[k], hi[k] = b.hi[k];
}

}  // namespace arbor
