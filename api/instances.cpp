/// arbor::Scene's instances: add_instance / set_transform, and the two-level structure built over
/// them (accel/instances/instance_accel.h): one structure per mesh, a top BVH over the placements.
#include <algorithm>
#include <cstring>
#include <string>

#include "accel/factory/make_accel.h"
#include "accel/instances/instance_accel.h"
#include "accel/select/auto_select.h"
#include "api/scene_impl.h"

namespace arbor {

namespace {

/// The transform of a caller's 12 numbers, checked; Error(invalid_argument) naming `fn` otherwise.
template <class Real>
accel::Affine checked_transform(const Real* transform, const char* fn) {
    if (!transform) throw Error(Error::Kind::invalid_argument, std::string(fn) + ": transform is null");
    accel::Affine a;
    for (std::size_t i = 0; i < 12; ++i) a.m[i] = double(transform[i]);
    const std::string problem = accel::check_affine(a);
    if (!problem.empty()) throw Error(Error::Kind::invalid_argument, std::string(fn) + ": transform: " + problem);
    return a;
}

/// Mesh g's triangles as a mesh of their own (vertex numbers from 0), with its box.
std::unique_ptr<accel::InstanceMesh> mesh_copy(const Scene::Impl& s, std::size_t g) {
    auto out = std::make_unique<accel::InstanceMesh>();
    const std::size_t first = s.first_prim[g];
    const std::size_t end = g + 1 < s.first_prim.size() ? s.first_prim[g + 1] : s.mesh.triangle_count();
    if (first == end) return out;
    // add_mesh appends each mesh's vertices together: its triangles use one range of them.
    const auto* idx = s.mesh.indices.data();
    const std::uint32_t lo = *std::min_element(idx + 3 * first, idx + 3 * end);
    const std::uint32_t hi = *std::max_element(idx + 3 * first, idx + 3 * end);
    out->x.assign(s.mesh.x.begin() + lo, s.mesh.x.begin() + hi + 1);
    out->y.assign(s.mesh.y.begin() + lo, s.mesh.y.begin() + hi + 1);
    out->z.assign(s.mesh.z.begin() + lo, s.mesh.z.begin() + hi + 1);
    out->indices.resize(3 * (end - first));
    for (std::size_t k = 0; k < out->indices.size(); ++k) out->indices[k] = idx[3 * first + k] - lo;
    const accel::TriangleView v = out->view();
    for (std::size_t t = 0; t < v.triangle_count(); ++t)
        if (v.triangle_is_finite(t)) out->bounds.grow(v.triangle_bounds(t));
    return out;
}

}  // namespace

std::uint32_t Scene::add_instance(std::uint32_t geom, const double transform[12]) {
    return guarded([&] {
        if (geom >= meshes())
            throw Error(Error::Kind::invalid_argument, "add_instance: geom " + std::to_string(geom) +
                                                           " is not in the scene (it holds " + std::to_string(meshes()) +
                                                           " meshes)");
        const accel::Affine a = checked_transform(transform, "add_instance");
        if (impl_->instances.size() >= invalid_id - 1)
            throw Error(Error::Kind::invalid_argument, "add_instance: the scene holds 2^32 - 1 instances");
        impl_->instances.push_back({geom, a});
        impl_->ready = false;
        impl_->accel.reset();
        impl_->placed = nullptr;
        impl_->accel_name.clear(), impl_->accel_reason.clear();
        return std::uint32_t(impl_->instances.size() - 1);
    });
}

std::uint32_t Scene::add_instance(std::uint32_t geom, const float transform[12]) {
    if (!transform) return add_instance(geom, static_cast<const double*>(nullptr));
    double d[12];
    for (int i = 0; i < 12; ++i) d[i] = transform[i];
    return add_instance(geom, d);
}

void Scene::set_transform(std::uint32_t instance, const double transform[12]) {
    guarded([&] {
        if (instance >= impl_->instances.size())
            throw Error(Error::Kind::invalid_argument, "set_transform: instance " + std::to_string(instance) +
                                                           " is not in the scene (it holds " +
                                                           std::to_string(impl_->instances.size()) + " instances)");
        impl_->instances[instance].transform = checked_transform(transform, "set_transform");
        // The bottoms do not change, but the top level does: rebuilt with the whole structure
        // at the next query.
        impl_->ready = false;
        impl_->accel.reset();
        impl_->placed = nullptr;
    });
}

std::size_t Scene::instances() const { return impl_->instances.size(); }

void Scene::Impl::build_instanced(accel::AccelKind kind, const accel::BuildConfig& cfg) {
    const std::size_t n_geom = first_prim.size();
    std::vector<char> has_instance(n_geom, 0);
    for (const Instance& i : instances) has_instance[i.geom] = 1;
    // Placements: the instances in id order, then each mesh without one, as it is.
    std::vector<accel::Placement> placements;
    placements.reserve(instances.size() + n_geom);
    for (std::size_t i = 0; i < instances.size(); ++i)
        placements.push_back(accel::Placement::make(instances[i].geom, std::uint32_t(i), instances[i].transform));
    for (std::size_t g = 0; g < n_geom; ++g)
        if (!has_instance[g]) placements.push_back(accel::Placement::make(std::uint32_t(g), invalid_id, accel::Affine{}));
    std::vector<accel::Bottom> bottoms(n_geom);
    std::string picks;
    std::size_t largest = 0, largest_size = 0;
    accel::AccelKind shown = kind == accel::AccelKind::automatic ? accel::AccelKind::bvh_sah : kind;
    arena->execute([&] {
        for (std::size_t g = 0; g < n_geom; ++g) {
            bottoms[g].mesh = mesh_copy(*this, g);
            const accel::TriangleView view = bottoms[g].mesh->view();
            accel::AccelKind k = kind;
            if (k == accel::AccelKind::automatic) {
                if (view.triangle_count() == 0) {
                    k = accel::AccelKind::bvh_sah;
                } else {
                    accel::AccelPick pick = accel::pick_accel(
                        k, accel::trace_job(view, {}, double(1 << 20), accel::Query::closest, accel::TracePath::best, cfg));
                    k = pick.kind;
                    bottoms[g].accel = std::move(pick.built);
                }
            }
            if (!bottoms[g].accel) bottoms[g].accel = accel::make_accel(k, view, cfg);
            picks += (g ? ", " : "") + std::string(accel::to_string(k));
            if (view.triangle_count() >= largest_size) largest = g, largest_size = view.triangle_count(), shown = k;
        }
    });
    (void)largest;
    auto two_level = std::make_unique<accel::InstanceAccel>(shown, std::move(bottoms), std::move(placements));
    placed = two_level.get();
    accel = std::move(two_level);
    accel_name = std::string(accel::to_string(shown));
    accel_reason = "instances: " + std::to_string(instances.size()) + " instances of " + std::to_string(n_geom) +
                   " meshes under a top BVH; per mesh: " + picks;
}

void Scene::Impl::locate_placed(std::uint32_t global, std::uint32_t& geom, std::uint32_t& prim, std::uint32_t& inst) const {
    const accel::Placement& p = placed->placements()[placed->placement_of(global)];
    geom = p.geom, prim = global - p.first, inst = p.id;
}

accel::Bounds Scene::Impl::world_bounds() const {
    if (instances.empty()) return bounds;
    if (placed) return placed->bounds();
    // Before the build: each mesh's box carried by each placement of it.
    std::vector<accel::Bounds> geom_box(first_prim.size());
    for (std::size_t g = 0; g < first_prim.size(); ++g) geom_box[g] = mesh_copy(*this, g)->bounds;
    std::vector<char> has_instance(first_prim.size(), 0);
    accel::Bounds out;
    for (const Instance& i : instances) {
        has_instance[i.geom] = 1;
        out.grow(accel::transform_bounds(i.transform, geom_box[i.geom]));
    }
    for (std::size_t g = 0; g < first_prim.size(); ++g)
        if (!has_instance[g]) out.grow(geom_box[g]);
    return out;
}

}  // namespace arbor
