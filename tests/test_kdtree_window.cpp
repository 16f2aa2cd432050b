// The rope walk's float point window (kdtree_traverse.h, point_window): descend and rope_next decide
// in float where the point at t is clearly away from a plane and fall back to the double crossings
// elsewhere. These cases check that they take the double walk's decisions exactly: descend against
// descend_exact at distances swept across the tolerance boundary of every split, and the whole walk
// (every leaf, every visit_point, in order) against a reference walk written here with the double
// checks everywhere (the walk before the window).
#include "accel/kdtree/kdtree_build.h"
#include "accel/kdtree/kdtree_traverse.h"
#include "engine/procedural.h"
#include "kdtree_checks.h"
#include "testing.h"

#include <doctest/doctest.h>

#include <cmath>
#include <random>

using namespace arbor;
using accel::Ray;
using accel::Vec3f;
namespace kd = accel::kd;

namespace {

const float inf = std::numeric_limits<float>::infinity();

/// The reference rope step: rope_next with every face's crossing and near check in double.
template <class LeafFn>
kd::RopeStep reference_next(const accel::KdTree& tree, const kd::RopeRay& s, double& t, std::uint32_t& node,
                            LeafFn& leaf_fn, unsigned& touched) {
    std::uint64_t visited = 0;
    const accel::KdNode* nodes = tree.nodes.data();
    const accel::KdLeaf& leaf = tree.leaves[nodes[node].index()];
    double t_exit = INFINITY, t_far[3] = {0, 0, 0}, t_near[3] = {0, 0, 0};
    int axis = -1;
    for (int k = 0; k < 3; ++k) {
        if (s.flat[k]) {
            const bool on_lo = s.o[k] == leaf.box.lo[k] && leaf.box.lo[k] != tree.box.lo[k];
            const bool on_hi = s.o[k] == leaf.box.hi[k] && leaf.box.hi[k] != tree.box.hi[k];
            if (on_lo || on_hi) touched |= 1u << k;
            continue;
        }
        t_far[k] = kd::cross_t(s, k, s.up[k] ? leaf.box.hi[k] : leaf.box.lo[k]);
        t_near[k] = kd::cross_t(s, k, s.up[k] ? leaf.box.lo[k] : leaf.box.hi[k]);
        if (t_far[k] < t_exit) t_exit = t_far[k], axis = k;
    }
    if (axis < 0) return kd::RopeStep::end;
    if (t_exit > s.t_end + s.tol[axis] * std::fabs(s.t_end)) return kd::RopeStep::end;
    bool corner = false, near_exit = false;
    for (int k = 0; k < 3; ++k) {
        if (s.flat[k]) continue;
        corner |= k != axis && t_far[k] == t_exit;
        near_exit |= (k != axis && kd::near_plane(s, k, t_far[k], t_exit)) || kd::near_plane(s, k, t_near[k], t_exit);
    }
    t = t_exit;
    const std::uint32_t rope = leaf.rope[accel::kd_face(axis, s.up[axis])];
    // The leaves around the exit point, but not this one (tested just before with the same ray).
    const std::uint32_t tested = nodes[node].index();
    auto others = [&](std::uint32_t li) { return li != tested && leaf_fn(li); };
    if (rope == accel::kd_no_rope)
        return near_exit && kd::visit_point<false>(nodes, s, t, others, visited) ? kd::RopeStep::stop : kd::RopeStep::end;
    node = kd::descend_exact(nodes, s, corner ? 0u : rope, t, near_exit, visited);
    if (near_exit && kd::visit_point<false>(nodes, s, t, others, visited)) return kd::RopeStep::stop;
    return kd::RopeStep::leaf;
}

/// The leaves the reference walk visits (best_t = +inf: the whole ray), tie sides of flat axes included.
std::vector<std::uint32_t> reference_leaves(const accel::KdTree& tree, const Ray& r) {
    std::vector<std::uint32_t> out;
    if (tree.empty() || !accel::ray_is_traceable(r)) return out;
    auto leaf_fn = [&](std::uint32_t li) {
        out.push_back(li);
        return false;
    };
    std::uint64_t visited = 0;
    kd::RopeRay s;
    double t0 = 0.0;
    switch (kd::rope_start(tree, r, s, t0)) {
    case kd::RopeStart::none: return out;
    case kd::RopeStart::point: kd::visit_point<false>(tree.nodes.data(), s, t0, leaf_fn, visited); return out;
    case kd::RopeStart::walk: break;
    }
    const auto pass = [&](const kd::RopeRay& ps, unsigned& touched) {
        double t = t0;
        bool near = false;
        std::uint32_t node = kd::descend_exact(tree.nodes.data(), ps, 0, t0, near, visited);
        if (near) kd::visit_point<false>(tree.nodes.data(), ps, t0, leaf_fn, visited);
        kd::RopeStep st = kd::RopeStep::leaf;
        for (std::size_t step = 0; step < kd::rope_max_steps(tree) && st == kd::RopeStep::leaf; ++step) {
            leaf_fn(tree.nodes[node].index());
            st = reference_next(tree, ps, t, node, leaf_fn, touched);
        }
    };
    unsigned touched = 0;
    pass(s, touched);
    if (touched == 0) return out;
    int flat_axes[3], nf = 0;
    for (int k = 0; k < 3; ++k)
        if (s.flat[k]) flat_axes[nf++] = k;
    for (unsigned combo = 1; combo < (1u << nf); ++combo) {
        kd::RopeRay other = s;
        for (int i = 0; i < nf; ++i)
            if (combo & (1u << i)) other.tie_right[flat_axes[i]] = !s.tie_right[flat_axes[i]];
        unsigned unused = 0;
        pass(other, unused);
    }
    return out;
}

std::vector<std::uint32_t> walk_leaves(const accel::KdTree& tree, const Ray& r) {
    std::vector<std::uint32_t> out;
    std::uint64_t visited = 0;
    const float never = inf;
    kd::walk_ropes<false>(tree, r, never, [&](std::uint32_t li) {
        out.push_back(li);
        return false;
    }, visited);
    return out;
}

/// A soup around an icosphere, moved by `offset` and scaled by `scale`.
engine::Mesh placed_mesh(float offset, float scale) {
    engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 3, 0.15f, 5);
    mesh.append(testing::random_soup(400, 0.15f, 3));
    testing::place(mesh, offset, scale);
    return mesh;
}

/// Rays aimed at the tree's planes: origins on split planes and leaf corners, random directions and
/// directions lying in the plane (+-0 components), and random rays into and inside the scene.
std::vector<Ray> plane_rays(const accel::KdTree& tree, const engine::Mesh& mesh, std::uint32_t seed) {
    const auto boxes = testing::kd_node_boxes(tree);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::vector<Ray> rays = testing::random_rays_into(mesh.bounds, 300, seed);
    const auto inside = testing::random_rays_inside(mesh.bounds, 300, seed + 1);
    rays.insert(rays.end(), inside.begin(), inside.end());
    const std::size_t step = tree.nodes.size() / 800 + 1;
    for (std::size_t i = 0; i < tree.nodes.size(); i += step) {
        const accel::KdNode n = tree.nodes[i];
        const accel::Bounds& b = boxes[i];
        Vec3f d = simd::normalize(Vec3f{g(rng), g(rng), g(rng)});
        if (n.is_leaf()) {
            const Vec3f corner{(i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y, (i & 4) ? b.lo.z : b.hi.z};
            rays.push_back({corner, 0.0f, d, inf});
            rays.push_back({corner - d * 2.0f, 0.0f, d, inf});
            d[i % 3] = (i & 8) ? -0.0f : 0.0f;
            rays.push_back({corner, 0.0f, d, inf});
            continue;
        }
        const int k = n.axis();
        Vec3f o{b.lo.x + u(rng) * (b.hi.x - b.lo.x), b.lo.y + u(rng) * (b.hi.y - b.lo.y), b.lo.z + u(rng) * (b.hi.z - b.lo.z)};
        o[k] = n.split;
        rays.push_back({o, 0.0f, d, inf});
        rays.push_back({o - d * 3.0f, 0.0f, d, inf});
        d[k] = (i & 16) ? -0.0f : 0.0f;  // lying in the split plane
        rays.push_back({o, 0.0f, d, inf});
    }
    return rays;
}

}  // namespace

TEST_CASE("kdtree window: descend takes descend_exact's side and near flag at every split, across the tolerance") {
    // Distances from each split's crossing tp, in units of the tolerance tol_k * |tp|: either side
    // of the boundary of near_plane (1), inside it, well away from it, and exactly on the plane.
    const double fractions[] = {0.0, 0.25, 0.5, 0.75, 0.9, 0.99, 0.999, 0.9999, 1.0, 1.0001, 1.001, 1.01, 1.1, 1.5, 2.0, 10.0, 1e3};
    for (const auto& placement : {std::pair{0.0f, 1.0f}, std::pair{1.0e6f, 1.0f}, std::pair{1e-3f, 1e-6f}}) {
        const float offset = placement.first, scale = placement.second;
        CAPTURE(offset);
        CAPTURE(scale);
        const engine::Mesh mesh = placed_mesh(offset, scale);
        const accel::KdTree tree = accel::build_kdtree(mesh.view());
        REQUIRE(tree.nodes.size() > 100);
        const std::vector<Ray> rays = plane_rays(tree, mesh, 11);
        std::size_t checked = 0, near_cases = 0, on_plane = 0, bad = 0;
        std::uint64_t visited = 0;
        std::mt19937 rng(5);
        for (const Ray& r : rays) {
            kd::RopeRay s;
            double t0 = 0.0;
            if (!accel::ray_is_traceable(r) || kd::rope_start(tree, r, s, t0) == kd::RopeStart::none) continue;
            // A few interior nodes per ray, each with its plane's crossing moved across the tolerance.
            for (int pick = 0; pick < 6; ++pick) {
                const std::uint32_t i = std::uint32_t(rng() % tree.nodes.size());
                const accel::KdNode n = tree.nodes[i];
                if (n.is_leaf() || s.flat[n.axis()]) continue;
                const int k = n.axis();
                const double tp = kd::cross_t(s, k, n.split);
                for (const double f : fractions)
                    for (const double sign : {1.0, -1.0}) {
                        double t = tp + sign * f * s.tol[k] * std::fabs(tp);
                        for (int nudge = -1; nudge <= 1; ++nudge) {
                            const double tn = nudge == 0 ? t : std::nextafter(t, nudge * INFINITY);
                            for (const std::uint32_t start : {0u, i}) {
                                bool near_fast = false, near_exact = false;
                                const std::uint32_t a =
                                    kd::descend(tree.nodes.data(), s, start, tn, kd::point_window(s, tn), near_fast, visited);
                                const std::uint32_t b = kd::descend_exact(tree.nodes.data(), s, start, tn, near_exact, visited);
                                ++checked;
                                near_cases += near_exact;
                                if (a != b || near_fast != near_exact) {
                                    ++bad;
                                    if (bad < 4) MESSAGE("node ", start, " t ", tn, " leaf ", a, " vs ", b, " near ", near_fast, " vs ", near_exact);
                                }
                            }
                        }
                    }
                // The same plane from both of its sides, exactly at the crossing: the side the ray moves into.
                bool nf = false, ne = false;
                const bool same = kd::descend(tree.nodes.data(), s, i, tp, kd::point_window(s, tp), nf, visited) ==
                                  kd::descend_exact(tree.nodes.data(), s, i, tp, ne, visited);
                bad += !same || nf != ne;
                ++on_plane;
            }
            // Flat axes: origins on the split planes with either tie side.
            for (int k = 0; k < 3; ++k)
                if (s.flat[k])
                    for (const bool tie : {false, true}) {
                        kd::RopeRay o = s;
                        o.tie_right[k] = tie;
                        bool near_fast = false, near_exact = false;
                        const std::uint32_t a = kd::descend(tree.nodes.data(), o, 0, t0, kd::point_window(o, t0), near_fast, visited);
                        const std::uint32_t b = kd::descend_exact(tree.nodes.data(), o, 0, t0, near_exact, visited);
                        ++checked;
                        bad += a != b || near_fast != near_exact;
                    }
        }
        CHECK(bad == 0);
        // The sweep reaches both sides of the tolerance boundary.
        CHECK(near_cases > checked / 10);
        CHECK(near_cases < checked * 9 / 10);
        CHECK(on_plane > 100);
    }
}

TEST_CASE("kdtree window: the rope walk visits exactly the reference walk's leaves, in order") {
    for (const auto& placement : {std::pair{0.0f, 1.0f}, std::pair{1.0e6f, 1.0f}, std::pair{1.0e7f, 10.0f}, std::pair{1e-3f, 1e-6f}}) {
        const float offset = placement.first, scale = placement.second;
        CAPTURE(offset);
        CAPTURE(scale);
        const engine::Mesh mesh = placed_mesh(offset, scale);
        const accel::KdTree tree = accel::build_kdtree(mesh.view());
        const std::vector<Ray> rays = plane_rays(tree, mesh, 21);
        std::size_t bad = 0, leaves = 0;
        for (const Ray& r : rays) {
            const auto a = walk_leaves(tree, r);
            const auto b = reference_leaves(tree, r);
            leaves += b.size();
            if (a != b && ++bad < 4) MESSAGE("ray org ", r.org.x, " ", r.org.y, " ", r.org.z, ": ", a.size(), " vs ", b.size(), " leaves");
        }
        CHECK(bad == 0);
        CHECK(leaves > rays.size());
    }
    // Grids and cubes: rays along grid lines and through vertices, every face on a split plane.
    for (const engine::Mesh& mesh : {testing::integer_grid(6), testing::integer_cubes(4)}) {
        const accel::KdTree tree = accel::build_kdtree(mesh.view());
        std::vector<Ray> rays = plane_rays(tree, mesh, 31);
        for (int a = -1; a <= 7; ++a)
            for (int b = -1; b <= 7; ++b) {
                rays.push_back({{float(a) - 1.0f, float(b) - 1.0f, 1.0f}, 0.0f, {1.0f, 1.0f, -1.0f}, inf});
                rays.push_back({{float(a) - 2.0f, float(b), -1.0f}, 0.0f, {1.0f, 0.0f, 1.0f}, inf});
                rays.push_back({{float(a), float(b) + 0.5f, -1.0f}, 0.0f, {0.0f, -0.0f, 1.0f}, inf});
                rays.push_back({{-1.0f, float(a), float(b)}, 0.0f, {1.0f, 0.0f, -0.0f}, inf});
            }
        std::size_t bad = 0;
        for (const Ray& r : rays) bad += walk_leaves(tree, r) != reference_leaves(tree, r);
        CHECK(bad == 0);
    }
}
