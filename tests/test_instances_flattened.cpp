// Instances against the same scene flattened (every placed copy's vertices carried over in double
// and rounded to float): rotations about skew axes, mirrors, non-uniform scales, a shear, small
// and flattened copies. Every ray farther than 1e-6 of the scene's diagonal from an edge of the
// triangles it hits gets the same answer (hit or miss, triangle, instance; t within 1e-6 relative,
// or, for hits nearer than the scene's size, within 1e-6 of the diagonal along the ray: the
// flattened corners are themselves rounded to float, ~6e-8 of the coordinates) from closest hit,
// any hit and all hits; closest points agree in world distance; inside agrees away from the
// surface.
#include "engine/procedural.h"
#include "instance_scenes.h"
#include "testing.h"

#include <arbor/arbor.h>
#include <doctest/doctest.h>

#include <cmath>

using namespace arbor;
using testing::Transform;

namespace {

struct Pair {
    std::vector<engine::Mesh> meshes;  ///< the meshes placed (geom ids of `placed`)
    std::vector<engine::Mesh> flat;    ///< per instance, its copy flattened (geom ids of `flattened`)
    Scene placed, flattened;
    double diagonal = 0;
    accel::Bounds box;

    Pair() {
        meshes.push_back(engine::make_icosphere({0, 0, 0}, 1.0f, 3, 0.05f, 2));
        meshes.push_back(engine::make_torus({0.2f, 0, 0}, 0.9f, 0.3f, 24, 12));
        for (const engine::Mesh& m : meshes) testing::add(placed, m);
        const std::vector<Transform> ts = testing::stiff_transforms();
        for (std::size_t k = 0; k < ts.size(); ++k) {
            const std::uint32_t g = std::uint32_t(k % meshes.size());
            CHECK(placed.add_instance(g, ts[k].data()) == k);
            flat.push_back(testing::flatten(meshes[g], ts[k]));
            testing::add(flattened, flat.back());
        }
        flattened.bounds(&box.lo.x, &box.hi.x);
        const accel::Vec3f e = box.extent();
        diagonal = std::sqrt(double(e.x) * e.x + double(e.y) * e.y + double(e.z) * e.z);
    }
    /// Whether hit h of `flattened` (flat = true) or of `placed` lies within 1e-6 of the diagonal of an edge.
    bool near_edge(const Hit& h, bool is_flat) const {
        if (!h.hit()) return false;
        const std::uint32_t copy = is_flat ? h.geom : h.inst;
        return testing::edge_distance(flat[copy], h.prim, h.u, h.v) < 1e-6 * diagonal;
    }
    /// The hit `placed` should give for hit h of `flattened`.
    bool agree(const Hit& f, const Hit& p) const {
        if (f.hit() != p.hit()) return false;
        if (!f.hit()) return p.inst == invalid_id && p.geom == invalid_id;
        return p.inst == f.geom && p.geom == f.geom % meshes.size() && p.prim == f.prim &&
               std::fabs(double(p.t) - double(f.t)) <= 1e-6 * std::max(std::fabs(double(f.t)), diagonal / length);
    }
    double length = 1.0;  ///< of the direction of the ray compared
};

std::vector<Ray> public_rays(const std::vector<accel::Ray>& in) {
    std::vector<Ray> out(in.size());
    std::memcpy(static_cast<void*>(out.data()), in.data(), in.size() * sizeof(Ray));
    return out;
}

}  // namespace

TEST_CASE("instances: closest, any and all hits agree with the flattened scene for every kind of transform") {
    for (const char* name : {"bvh-sah", "kdtree", "lbvh", "brute"}) {
        CAPTURE(name);
        Pair s;
        BuildOptions o;
        o.accel = name;
        s.placed.build(o);
        s.flattened.build(o);
        const auto rays = public_rays(testing::three_kinds(s.box, 2500, 5));
        const auto f = s.flattened.intersect(rays), p = s.placed.intersect(rays);
        const auto fo = s.flattened.occluded(rays), po = s.placed.occluded(rays);
        std::size_t compared = 0, hits = 0, differ = 0, occ_differ = 0;
        std::vector<char> away(rays.size(), 0);
        for (std::size_t i = 0; i < rays.size(); ++i) {
            if (s.near_edge(f[i], true) || s.near_edge(p[i], false)) continue;
            away[i] = 1;
            ++compared, hits += f[i].hit();
            s.length = std::sqrt(double(rays[i].dir[0]) * rays[i].dir[0] + double(rays[i].dir[1]) * rays[i].dir[1] +
                                 double(rays[i].dir[2]) * rays[i].dir[2]);
            if (!s.agree(f[i], p[i])) {
                ++differ;
                if (differ <= 3)
                    MESSAGE("ray ", i, ": flat t ", f[i].t, " geom ", f[i].geom, " prim ", f[i].prim, "; placed t ", p[i].t,
                            " inst ", p[i].inst, " prim ", p[i].prim);
            }
            occ_differ += fo[i] != po[i];
        }
        CHECK(compared > rays.size() * 9 / 10);
        CHECK(hits > compared / 10);
        CHECK(differ == 0);
        CHECK(occ_differ == 0);
        // All hits: rows of rays whose every crossing is away from the edges.
        const std::size_t k = 8;
        std::vector<Hit> fa(rays.size() * k), pa(rays.size() * k);
        std::vector<std::int32_t> fc(rays.size()), pc(rays.size());
        s.flattened.intersect_all(RayArrays::of(rays.data(), rays.size()), k, fa.data(), fc.data());
        s.placed.intersect_all(RayArrays::of(rays.data(), rays.size()), k, pa.data(), pc.data());
        std::size_t rows = 0, all_differ = 0, multi = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            bool clean = fc[i] <= std::int32_t(k) && pc[i] <= std::int32_t(k);
            for (std::size_t j = 0; clean && j < k; ++j)
                clean = !s.near_edge(fa[i * k + j], true) && !s.near_edge(pa[i * k + j], false);
            if (!clean) continue;
            ++rows, multi += fc[i] > 1;
            s.length = std::sqrt(double(rays[i].dir[0]) * rays[i].dir[0] + double(rays[i].dir[1]) * rays[i].dir[1] +
                                 double(rays[i].dir[2]) * rays[i].dir[2]);
            all_differ += fc[i] != pc[i];
            for (std::size_t j = 0; j < std::size_t(std::min(fc[i], pc[i])); ++j)
                all_differ += !s.agree(fa[i * k + j], pa[i * k + j]);
        }
        CHECK(rows > rays.size() * 8 / 10);
        CHECK(multi > rows / 10);
        CHECK(all_differ == 0);
    }
}

TEST_CASE("instances: closest points and inside agree with the flattened scene, in world distances") {
    Pair s;
    const accel::Vec3f e = s.box.extent();
    std::vector<float> xyz;
    std::uint32_t state = 12345;
    const auto next = [&] {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) / float(1u << 24);
    };
    for (int i = 0; i < 600; ++i)
        for (int c = 0; c < 3; ++c) xyz.push_back(s.box.lo[c] - 0.1f * e[c] + 1.2f * e[c] * next());
    const auto f = s.flattened.closest_point(xyz), p = s.placed.closest_point(xyz);
    std::size_t differ = 0, prim_differ = 0;
    for (std::size_t i = 0; i < f.size(); ++i) {
        REQUIRE(f[i].found());
        REQUIRE(p[i].found());
        const double tol = 1e-6 * s.diagonal;
        differ += std::fabs(double(f[i].distance) - double(p[i].distance)) > tol;
        for (int c = 0; c < 3; ++c) differ += std::fabs(double(f[i].point[c]) - double(p[i].point[c])) > 1e-5 * s.diagonal;
        prim_differ += f[i].geom != p[i].inst || f[i].prim != p[i].prim || p[i].geom != f[i].geom % 2;
    }
    CHECK(differ == 0);
    // The same triangle, but for points whose nearest two triangles are within rounding (a shared edge or vertex).
    CHECK(prim_differ < f.size() / 20);
    // Within max_distance only.
    const auto near = s.placed.closest_point(xyz, 0.05f);
    std::size_t reach_wrong = 0;
    for (std::size_t i = 0; i < f.size(); ++i) reach_wrong += near[i].found() != (f[i].distance <= 0.05f);
    CHECK(reach_wrong <= 2);  // distances at 0.05 within rounding
    // Inside: away from the surface (closest distance above 1e-5 of the diagonal).
    const auto fi = s.flattened.inside(xyz), pi = s.placed.inside(xyz);
    std::size_t in = 0, inside_differ = 0;
    for (std::size_t i = 0; i < f.size(); ++i) {
        if (f[i].distance < 1e-5 * s.diagonal) continue;
        in += fi[i], inside_differ += fi[i] != pi[i];
    }
    CHECK(inside_differ == 0);
    CHECK(in > 5);
}
