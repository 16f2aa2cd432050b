// The API's later queries beside each other: winding numbers after update_vertices see the new
// positions (the tree is made again); a scene with instances refuses winding numbers and
// update_vertices by name instead of answering over the meshes as added, and still answers
// inside and signed_distance by parity in world space.
#include <arbor/arbor.h>
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "api_shapes.h"

namespace {

/// The error's message when `f` throws arbor::Error of kind invalid_argument, else "".
template <class F>
std::string invalid_argument(F&& f) {
    try {
        f();
    } catch (const arbor::Error& e) {
        if (e.kind() == arbor::Error::Kind::invalid_argument) return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("api together: winding numbers after update_vertices are those of the new positions") {
    const arbor::testing::TwoMeshes m;
    arbor::Scene scene;
    m.add_to(scene);
    scene.build({"bvh-sah"});
    const std::vector<float> centre{0.0f, 0.0f, 0.0f};  // inside the sphere (geom 0)
    CHECK(scene.winding_number(centre)[0] == doctest::Approx(1.0).epsilon(0.05));
    // Move the sphere 10 units along x: the centre is now outside it.
    std::vector<float> moved = arbor::testing::TwoMeshes::positions(m.sphere);
    for (std::size_t i = 0; i < moved.size(); i += 3) moved[i] += 10.0f;
    for (const char* mode : {"refit", "rebuild"}) {
        arbor::Scene s2;
        m.add_to(s2);
        s2.build({"bvh-sah"});
        CHECK(s2.winding_number(centre)[0] == doctest::Approx(1.0).epsilon(0.05));  // the tree is made
        arbor::UpdateOptions u;
        u.mode = mode;
        s2.update_vertices(0, moved, u);
        CAPTURE(mode);
        CHECK(std::abs(s2.winding_number(centre)[0]) < 0.05);  // the tree of the old positions would say 1
        CHECK(s2.winding_number({10.0f, 0.0f, 0.0f})[0] == doctest::Approx(1.0).epsilon(0.05));
        CHECK(s2.inside({10.0f, 0.0f, 0.0f}, arbor::InsideMethod::winding, {}, {})[0]);
    }
}

TEST_CASE("api together: a scene with instances refuses winding numbers and update_vertices by name") {
    const arbor::testing::TwoMeshes m;
    arbor::Scene scene;
    m.add_to(scene);
    const double shift[12] = {1, 0, 0, 5, 0, 1, 0, 0, 0, 0, 1, 0};
    scene.add_instance(0, shift);
    scene.build({"bvh-sah"});
    const std::vector<float> p{5.0f, 0.0f, 0.0f};  // the centre of the placed sphere
    CHECK(invalid_argument([&] { (void)scene.winding_number(p); }).find("winding_number") != std::string::npos);
    CHECK(invalid_argument([&] { (void)scene.inside(p, arbor::InsideMethod::winding, {}, {}); }).find("inside") !=
          std::string::npos);
    CHECK(invalid_argument([&] { scene.update_vertices(0, arbor::testing::TwoMeshes::positions(m.sphere)); })
              .find("update_vertices") != std::string::npos);
    // Parity answers in world space: inside the placed copy, outside where the mesh was added.
    CHECK(scene.inside(p)[0]);
    CHECK_FALSE(scene.inside({0.0f, 0.0f, 0.0f})[0]);
}
