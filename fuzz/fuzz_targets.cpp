#include "fuzz/fuzz_targets.h"

#include "accel/factory/make_accel.h"
#include "accel/structures/brute_accel.h"
#include "engine/error.h"
#include "engine/mesh_loader.h"
#include "engine/obj_loader.h"
#include "engine/procedural.h"
#include "engine/rayfile.h"
#include "stress/run.h"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace arbor::fuzz {

namespace {

void require(bool ok, const std::string& what) {
    if (!ok) throw FuzzFinding(what);
}

std::string describe(const accel::Ray& r, const accel::Hit& ref, const accel::Hit& got) {
    char buf[400];
    std::snprintf(buf, sizeof buf, "ray o=(%a %a %a) d=(%a %a %a) t=[%a, %a]: brute t=%a prim=%u, got t=%a prim=%u", r.org.x,
                  r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z, r.tnear, r.tfar, ref.t, ref.prim, got.t, got.prim);
    return buf;
}

/// Brute force's closest hits on `rays`; untraceable rays must miss.
std::vector<accel::Hit> brute_answers(const accel::BruteAccel& brute, std::span<const accel::Ray> rays) {
    std::vector<accel::Hit> ref(rays.size());
    brute.trace(rays, ref, {accel::Query::closest, accel::TracePath::scalar});
    for (std::size_t i = 0; i < rays.size(); ++i)
        require(accel::ray_is_traceable(rays[i]) || !ref[i].is_hit(), "brute: an untraceable ray hit");
    return ref;
}

/// check_structure with brute's answers `ref` given.
void check_paths(const accel::Accel& a, const accel::BruteAccel& brute, std::span<const accel::Ray> rays,
                 const std::vector<accel::Hit>& ref) {
    require(a.stats().dropped_nonfinite == brute.stats().dropped_nonfinite,
            std::string(accel::to_string(a.kind())) + ": dropped a different number of triangles");
    std::vector<accel::Hit> got(rays.size()), any(rays.size());
    for (accel::TracePath path : stress::paths_of(a)) {
        a.trace(rays, got, {accel::Query::closest, path});
        a.trace(rays, any, {accel::Query::any, path});
        const std::string where = std::string(accel::to_string(a.kind())) + "/" + std::string(accel::to_string(path));
        for (std::size_t i = 0; i < rays.size(); ++i) {
            require(accel::hits_agree(ref[i], got[i]), where + ": closest hit differs from brute on " + describe(rays[i], ref[i], got[i]));
            require(any[i].is_hit() == ref[i].is_hit(), where + ": any hit differs from brute on " + describe(rays[i], ref[i], any[i]));
            if (any[i].is_hit())
                require(any[i].t >= rays[i].tnear && any[i].t <= rays[i].tfar, where + ": any hit outside [tnear, tfar]");
        }
    }
}

/// Every structure and path against brute force on `rays` (check_structure).
void check_structures(const accel::TriangleView& tris, const std::vector<accel::Ray>& rays) {
    const accel::BruteAccel brute(tris);
    const std::vector<accel::Hit> ref = brute_answers(brute, rays);
    static const std::vector<accel::AccelKind> kinds = stress::buildable_kinds();
    for (accel::AccelKind kind : kinds)
        if (kind != accel::AccelKind::brute) check_paths(*accel::make_accel(kind, tris), brute, rays, ref);
    // The kd-tree's SIMD paths of its other walks too (the default: tight cells; KdBlockConfig::walk).
    for (const accel::KdWalk walk : {accel::KdWalk::cells, accel::KdWalk::ropes}) {
        accel::BuildConfig cfg;
        cfg.kd_blocks.walk = walk;
        check_paths(*accel::make_accel(accel::AccelKind::kdtree, tris, cfg), brute, rays, ref);
    }
}

/// A few rays into the bounds of a mesh (deterministic), axis-parallel and oblique.
std::vector<accel::Ray> probe_rays(const engine::Mesh& m) {
    std::vector<accel::Ray> rays;
    const accel::Bounds b = m.bounds;
    const accel::Vec3f c = b.lo * 0.5f + b.hi * 0.5f;
    std::uint64_t s = 0x9E3779B97F4A7C15ull;
    auto next = [&] {
        s ^= s << 13, s ^= s >> 7, s ^= s << 17;
        return float(s >> 40) / 16777216.0f;
    };
    for (int i = 0; i < 24; ++i) {
        const std::uint32_t v = m.indices[std::size_t(i) * 7 % m.indices.size()];
        const accel::Vec3f target{m.x[v], m.y[v], m.z[v]};
        const accel::Vec3f from{c.x + (next() - 0.5f) * 4.0f * (b.hi.x - b.lo.x + 1.0f), c.y + (next() - 0.5f) * 4.0f * (b.hi.y - b.lo.y + 1.0f),
                                c.z + (next() - 0.5f) * 4.0f * (b.hi.z - b.lo.z + 1.0f)};
        rays.push_back({from, 0.0f, target - from, INFINITY});
        accel::Vec3f axis{0.0f, 0.0f, 0.0f};
        axis[i % 3] = i % 2 ? 1.0f : -1.0f;
        accel::Vec3f o = target;
        o[i % 3] -= axis[i % 3] * 2.0f * (std::fabs(target[i % 3]) + 1.0f);
        rays.push_back({o, 0.0f, axis, INFINITY});
    }
    return rays;
}

}  // namespace

namespace {

/// The contract of every loaded mesh: triangles, indices and attributes in range, finite vertices,
/// one-line warnings; small meshes are traced by every structure and path against brute force.
void check_mesh(const engine::Mesh& mesh, const engine::Warnings& warnings) {
    require(mesh.triangle_count() > 0, "loaded a mesh without triangles");
    require(mesh.indices.size() % 3 == 0, "index count not a multiple of 3");
    for (std::uint32_t i : mesh.indices) require(i < mesh.vertex_count(), "index out of range");
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        require(std::isfinite(mesh.x[v]) && std::isfinite(mesh.y[v]) && std::isfinite(mesh.z[v]), "non-finite vertex loaded");
    require(mesh.material.empty() || mesh.material.size() == mesh.triangle_count(), "material list size");
    for (std::uint32_t m : mesh.material) require(m < mesh.materials.size(), "material index out of range");
    require(mesh.normal_index.empty() || mesh.normal_index.size() == mesh.indices.size(), "normal index count");
    for (std::uint32_t n : mesh.normal_index) require(n == engine::no_attribute || n < mesh.normals.size(), "normal index out of range");
    require(mesh.uv_index.empty() || mesh.uv_index.size() == mesh.indices.size(), "uv index count");
    for (std::uint32_t t : mesh.uv_index) require(t == engine::no_attribute || t < mesh.uvs.size(), "uv index out of range");
    require(mesh.colors.empty() || mesh.colors.size() == mesh.vertex_count(), "vertex colour count");
    for (const std::string& w : warnings.lines) require(w.find('\n') == std::string::npos, "warning with a line break");
    if (mesh.triangle_count() <= 512) check_structures(mesh.view(), probe_rays(mesh));
}

}  // namespace

const engine::Mesh& ray_scene() {
    static const engine::Mesh scene = [] {
        engine::Mesh m = engine::make_icosphere({0, 0, 0}, 1.0f, 1, 0.1f, 3);
        m.append(engine::make_box({-2, -2, -2}, {2, -1.5f, 2}));
        m.append(engine::make_ground(2.0f, 0.0f, 0.0f, 3.0f));
        m.compute_bounds();
        return m;
    }();
    return scene;
}

void check_structure(const accel::Accel& a, const accel::TriangleView& tris, std::span<const accel::Ray> rays) {
    const accel::BruteAccel brute(tris);
    check_paths(a, brute, rays, brute_answers(brute, rays));
}

void fuzz_obj(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    engine::Warnings warnings;
    engine::Mesh mesh;
    try {
        // A base directory that does not exist: mtllib names must not reach real files.
        mesh = engine::load_obj_text(text, "fuzz.obj", "/nonexistent-arbor-fuzz/", warnings);
    } catch (const engine::InputError& e) {
        require(std::string(e.what()).find('\n') == std::string::npos, "error with a line break");
        return;
    }
    check_mesh(mesh, warnings);
}

void fuzz_mesh(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    engine::Warnings warnings;
    engine::Mesh mesh;
    try {
        mesh = engine::load_mesh_bytes(bytes, "fuzz.mesh", "", warnings, false);
    } catch (const engine::InputError& e) {
        require(std::string(e.what()).find('\n') == std::string::npos, "error with a line break");
        return;
    }
    check_mesh(mesh, warnings);
}

void fuzz_rays(const std::uint8_t* data, std::size_t size) {
    const std::span<const unsigned char> bytes(data, size);
    try {
        const auto hits = engine::parse_hits(bytes, "fuzz.hits");
        require(16 + hits.size() * sizeof(accel::Hit) == size, "hit count does not match the size");
    } catch (const engine::InputError&) {
    }
    std::vector<accel::Ray> rays;
    try {
        rays = engine::parse_rays(bytes, "fuzz.rays");
    } catch (const engine::InputError&) {
        return;
    }
    require(16 + rays.size() * sizeof(accel::Ray) == size, "ray count does not match the size");
    if (rays.size() > 256) rays.resize(256);
    check_structures(ray_scene().view(), rays);
}

}  // namespace arbor::fuzz
