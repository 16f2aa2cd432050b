// Generalized winding numbers (accel/core/winding_tree.h): the exact sum against a long-double
// oracle on stiff meshes and stiff points, the hierarchical trees of every structure within their
// own error bound, exact values on the surface of a closed box, and thread-count independence.
#include "accel/factory/make_accel.h"
#include "engine/procedural.h"
#include "query_check.h"
#include "winding_check.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <bit>
#include <cmath>
#include <limits>

using namespace arbor;
using accel::Vec3f;

namespace {

#if defined(ARBOR_SANITIZED_BUILD)
constexpr std::size_t per_kind = 8;
constexpr std::size_t thread_points = 60;  // (brute's sums over every triangle dominate there)
#else
constexpr std::size_t per_kind = 40;
constexpr std::size_t thread_points = 200;
#endif

/// The stiff meshes of the oracle tests, by name.
std::vector<std::pair<std::string, engine::Mesh>> stiff_meshes() {
    std::vector<std::pair<std::string, engine::Mesh>> out;
    const engine::Mesh sphere = engine::make_icosphere({0.1f, -0.2f, 0.3f}, 1.0f, 3, 0.1f, 4);
    out.push_back({"sphere", sphere});
    out.push_back({"sphere at 1e6", testing::moved(sphere, 1.0f, {1e6f, -1e6f, 5e5f})});
    out.push_back({"sphere at 1e-6", testing::moved(sphere, 1e-6f, {0.0f, 0.0f, 0.0f})});
    out.push_back({"slivers", testing::slivers()});
    out.push_back({"sphere with holes", testing::without_faces(sphere, 100, 3)});
    out.push_back({"flipped sphere", testing::flipped(sphere)});
    engine::Mesh dup = testing::doubled(sphere);
    dup.append(testing::flipped(engine::make_icosphere({3.0f, 0.0f, 0.0f}, 0.5f, 2)));
    dup.compute_bounds();
    out.push_back({"doubled sphere and a flipped one", dup});
    engine::Mesh two = engine::make_icosphere({0.0f, 0.0f, 0.0f}, 1.0f, 3);
    two.append(engine::make_torus({0.7f, 0.0f, 0.0f}, 0.8f, 0.4f, 24, 12));  // overlapping closed parts
    two.compute_bounds();
    out.push_back({"overlapping sphere and torus", two});
    out.push_back({"grid box", testing::grid_box(-1.0f, 1.0f, 6)});
    return out;
}

std::vector<std::unique_ptr<accel::WindingTree>> trees_of(const std::vector<testing::NamedAccel>& structures,
                                                          const accel::TriangleView& v) {
    std::vector<std::unique_ptr<accel::WindingTree>> out;
    for (const auto& s : structures) out.push_back(s.accel->make_winding_tree(v));
    return out;
}

}  // namespace

TEST_CASE("winding: the exact sum matches the long-double oracle to 1e-9 on stiff meshes and points") {
    // Absolute 1e-9 (winding numbers are O(1)). Points: on faces, at vertices, on edges (midpoints
    // and 1/8 along), in the box grown by 10%, and up to 1000 diagonals away (query_points).
    // Slivers are the exception on their own surface: there the solid angle's numerator and
    // denominator both cancel (0/0 in the limit), beyond what long double recovers, so the library
    // (exact numerator, long-double denominator) and the oracle (long double throughout) agree to
    // 1e-7 only; an 80-digit evaluation (mpmath) differed from both by up to 3e-7 at such points.
    for (const auto& named : stiff_meshes()) {
        // (Not a structured binding: clang 14 cannot capture one, and CAPTURE makes a lambda.)
        const std::string& name = named.first;
        const engine::Mesh& mesh = named.second;
        CAPTURE(name);
        std::vector<Vec3f> points = testing::query_points(mesh, per_kind, 11);
        const auto exact = accel::make_exact_winding(mesh.view());
        CHECK(exact->method() == "exact");
        if (name == "slivers") {
            const std::vector<Vec3f> surface(points.begin(), points.begin() + std::ptrdiff_t(3 * per_kind));
            CHECK(testing::check_tree(*exact, mesh.view(), surface, 2.0).worst_vs_oracle <= 1e-7);
            points.erase(points.begin(), points.begin() + std::ptrdiff_t(3 * per_kind));
        }
        const testing::TreeCheck r = testing::check_tree(*exact, mesh.view(), points, accel::default_winding_beta);
        CHECK(r.worst_vs_oracle <= 1e-9);
        CHECK(r.largest_bound == 0.0);
    }
    // A real open scan and a closed model.
    testing::for_each_shared_mesh([&](const std::string& path, const engine::Mesh& mesh) {
        if (path.find("stanford-bunny") == std::string::npos && path.find("spot") == std::string::npos) return;
        const auto points = testing::query_points(mesh, per_kind / 2, 12);
        const testing::TreeCheck r =
            testing::check_tree(*accel::make_exact_winding(mesh.view()), mesh.view(), points, 2.0);
        CHECK(r.worst_vs_oracle <= 1e-9);
    });
}

TEST_CASE("winding: every structure's tree stays within its error bound, and beta = inf is exact") {
    for (const auto& named : stiff_meshes()) {
        // (Not a structured binding: clang 14 cannot capture one, and CAPTURE makes a lambda.)
        const std::string& name = named.first;
        const engine::Mesh& mesh = named.second;
        CAPTURE(name);
        const auto points = testing::query_points(mesh, per_kind, 13);
        const auto structures = testing::query_structures(mesh.view(), true);
        const auto trees = trees_of(structures, mesh.view());
        const testing::Reference ref = testing::reference(mesh.view(), points);
        for (std::size_t k = 0; k < structures.size(); ++k) {
            CAPTURE(structures[k].name);
            const accel::WindingTree& tree = *trees[k];
            const std::string method(tree.method());
            if (structures[k].name == "brute")
                CHECK(method == "exact");
            else if (structures[k].name == "kdtree")
                CHECK(method == "bvh2 (internal)");
            else if (structures[k].name.ends_with("/scalar"))
                CHECK(method == "bvh2");
            else
                CHECK(method.starts_with("wide"));
            const testing::TreeCheck fast = testing::check_tree(tree, ref, points, 2.0);
            CHECK(fast.worst_bound_excess <= 1e-12);
            if (method != "exact" && mesh.triangle_count() > 500) CHECK(fast.largest_bound > 0.0);  // dipoles were used
            const testing::TreeCheck tight = testing::check_tree(tree, ref, points, 8.0);
            CHECK(tight.worst_bound_excess <= 1e-12);
            const testing::TreeCheck all =
                testing::check_tree(tree, ref, points, std::numeric_limits<double>::infinity());
            CHECK(all.worst_vs_oracle <= (name == "slivers" ? 1e-7 : 1e-9));  // as in the case above
            CHECK(all.largest_bound == 0.0);
        }
    }
}

TEST_CASE("winding: the fast error on the shared models, and points far away") {
    // The measured error at beta = 2 next to the bound; far away (>= 10 diagonals) one dipole
    // answers, with an error far below 1e-3.
    testing::for_each_shared_mesh([&](const std::string& path, const engine::Mesh& mesh) {
        if (path.find("spot") == std::string::npos && path.find("stanford-bunny") == std::string::npos) return;
        const auto bvh = accel::make_accel(accel::AccelKind::bvh_sah, mesh.view());
        const auto tree = bvh->make_winding_tree(mesh.view());
        const auto points = testing::query_points(mesh, per_kind, 14);
        const testing::TreeCheck r = testing::check_tree(*tree, mesh.view(), points, 2.0);
        CHECK(r.worst_bound_excess <= 1e-12);
        MESSAGE(path << ": beta 2, " << tree->method() << ", worst |fast - oracle| " << r.worst_vs_oracle
                     << ", largest bound " << r.largest_bound);
        std::vector<Vec3f> far;
        const float diag = simd::length(mesh.bounds.extent());
        for (const Vec3f& p : points)
            if (simd::length(p - mesh.bounds.center()) > 10.0f * diag) far.push_back(p);
        REQUIRE(far.size() >= per_kind / 2);
        CHECK(testing::check_tree(*tree, mesh.view(), far, 2.0).worst_vs_oracle < 1e-3);
    });
}

TEST_CASE("winding: on the surface of a closed box, 1/2 on faces, 1/4 on edges, 1/8 at corners") {
    // Points exactly in the faces' planes get nothing from the faces they lie in (solid_angle.h);
    // what the rest subtends is the interior's share of the directions. The hierarchical trees
    // give the same within their bound (coplanar dipoles give ~0 too).
    const engine::Mesh box = testing::grid_box(-1.0f, 1.0f, 8);
    std::vector<Vec3f> points;
    std::vector<double> expect;
    for (int i = 0; i < 16; ++i) {
        const float s = -0.95f + 0.11f * float(i), t = 0.83f - 0.1f * float(i);
        points.push_back({1.0f, s, t}), expect.push_back(0.5);  // face (also on grid lines: s = 0.25 ...)
        points.push_back({s, -1.0f, t}), expect.push_back(0.5);
        points.push_back({1.0f, 1.0f, s}), expect.push_back(0.25);  // edge
        points.push_back({s, -1.0f, -1.0f}), expect.push_back(0.25);
    }
    for (float x : {-1.0f, 1.0f})
        for (float y : {-1.0f, 1.0f})
            for (float z : {-1.0f, 1.0f}) points.push_back({x, y, z}), expect.push_back(0.125);
    points.push_back({0.5f, 0.25f, 0.0f}), expect.push_back(1.0);  // inside on grid planes of no face
    points.push_back({1.5f, 0.25f, 0.0f}), expect.push_back(0.0);
    for (const auto& s : testing::query_structures(box.view(), false)) {
        CAPTURE(s.name);
        const auto tree = s.accel->make_winding_tree(box.view());
        std::vector<double> w(points.size()), bound(points.size());
        tree->winding_numbers(points, 2.0, w, bound);
        for (std::size_t i = 0; i < points.size(); ++i) {
            CAPTURE(i);
            CHECK(std::fabs(w[i] - expect[i]) <= bound[i] + 1e-12);
        }
        tree->winding_numbers(points, std::numeric_limits<double>::infinity(), w, bound);
        for (std::size_t i = 0; i < points.size(); ++i) CHECK(std::fabs(w[i] - expect[i]) <= 1e-12);
    }
}

TEST_CASE("winding: non-finite points are NaN, an empty scene is 0") {
    const engine::Mesh sphere = engine::make_icosphere({0, 0, 0}, 1.0f, 2);
    const std::vector<Vec3f> odd = {{NAN, 0, 0}, {0, INFINITY, 0}, {0, 0, 0}, {1e30f, 0, 0}};
    for (const auto& s : testing::query_structures(sphere.view(), false)) {
        CAPTURE(s.name);
        std::vector<double> w(odd.size()), bound(odd.size());
        s.accel->make_winding_tree(sphere.view())->winding_numbers(odd, 2.0, w, bound);
        CHECK(std::isnan(w[0]));
        CHECK(std::isnan(w[1]));
        CHECK(std::fabs(w[2] - 1.0) <= bound[2] + 1e-9);
        CHECK(std::fabs(w[3]) <= bound[3] + 1e-12);
    }
    const engine::Mesh empty;
    for (const auto& s : testing::query_structures(empty.view(), false)) {
        CAPTURE(s.name);
        std::vector<double> w(1, 7.0);
        s.accel->make_winding_tree(empty.view())->winding_numbers(std::vector<Vec3f>{{0, 0, 0}}, 2.0, w);
        CHECK(w[0] == 0.0);
    }
}

TEST_CASE("winding: trees and answers are the same with 1 and 2 threads") {
    const engine::Mesh mesh = testing::without_faces(engine::make_icosphere({0, 0, 0}, 1.0f, 5, 0.1f, 2), 50, 1);
    const auto points = testing::query_points(mesh, thread_points, 15);
    const auto run = [&](int threads) {
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        std::vector<std::vector<double>> out;
        for (const auto& s : testing::query_structures(mesh.view(), false)) {
            std::vector<double> w(points.size());
            s.accel->make_winding_tree(mesh.view())->winding_numbers(points, 2.0, w);
            out.push_back(w);
        }
        return out;
    };
    const auto one = run(1), two = run(2);
    REQUIRE(one.size() == two.size());
    for (std::size_t k = 0; k < one.size(); ++k)
        for (std::size_t i = 0; i < points.size(); ++i)
            CHECK(std::bit_cast<std::uint64_t>(one[k][i]) == std::bit_cast<std::uint64_t>(two[k][i]));
}
