// Bad instances: unknown geometry or instance ids, null, NaN or infinite transforms and singular
// ones are refused with Error(invalid_argument) naming the call and the problem, and leave the
// scene as it was.
#include "engine/procedural.h"
#include "instance_scenes.h"

#include <arbor/arbor.h>
#include <doctest/doctest.h>

#include <cmath>
#include <string>

using namespace arbor;

namespace {

/// The message of the Error(invalid_argument) f throws ("" when it throws none or another kind).
template <class F>
std::string refusal(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.kind() == Error::Kind::invalid_argument ? e.what() : "";
    }
    return "";
}

bool mentions(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("instances: unknown ids and bad transforms are refused with a message naming the problem") {
    Scene s;
    testing::add(s, engine::make_box({0, 0, 0}, {1, 1, 1}));
    const double id[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    CHECK(mentions(refusal([&] { s.add_instance(1, id); }), "add_instance: geom 1 is not in the scene"));
    CHECK(mentions(refusal([&] { s.add_instance(0, static_cast<const double*>(nullptr)); }), "add_instance: transform is null"));
    CHECK(mentions(refusal([&] { s.add_instance(0, static_cast<const float*>(nullptr)); }), "add_instance: transform is null"));
    double bad[12];
    std::copy(id, id + 12, bad);
    bad[6] = NAN;
    CHECK(mentions(refusal([&] { s.add_instance(0, bad); }), "entry [1][2] is not finite"));
    bad[6] = 0, bad[3] = INFINITY;
    CHECK(mentions(refusal([&] { s.add_instance(0, bad); }), "entry [0][3] is not finite"));
    bad[3] = 0, bad[10] = 0;  // z collapses: singular
    CHECK(mentions(refusal([&] { s.add_instance(0, bad); }), "singular"));
    const double rank2[12] = {1, 2, 3, 0, 2, 4, 6, 0, 0, 0, 1, 0};  // two parallel rows
    CHECK(mentions(refusal([&] { s.add_instance(0, rank2); }), "singular"));
    const float flat[12] = {1, 0, 0, 0, 0, 1, 0, 0, 1, 1, 1e-14f, 0};  // det 1e-14: numerically singular
    CHECK(mentions(refusal([&] { s.add_instance(0, flat); }), "singular"));
    CHECK(s.instances() == 0);
    CHECK(mentions(refusal([&] { s.set_transform(0, id); }), "set_transform: instance 0 is not in the scene"));
    // Nothing was added: the scene still answers as the plain box.
    const std::vector<Ray> rays = {Ray{{0.5f, 0.5f, -1}, 0, {0, 0, 1}, INFINITY}};
    CHECK(s.intersect(rays)[0].inst == invalid_id);
    CHECK(s.intersect(rays)[0].t == 1.0f);
    // A good instance, then a bad move of it, which leaves it where it was.
    CHECK(s.add_instance(0, id) == 0);
    CHECK(mentions(refusal([&] { s.set_transform(0, bad); }), "set_transform: transform: the 3x3 part is singular"));
    CHECK(s.intersect(rays)[0].inst == 0);
    CHECK(s.intersect(rays)[0].t == 1.0f);
    // set_transform moves it: the next query sees the move.
    const double up[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0.5};
    s.set_transform(0, up);
    CHECK(s.intersect(rays)[0].t == 1.5f);
}

TEST_CASE("instances: a mirrored instance turns its normals over, and mirrored and scaled ones answer in world units") {
    Scene s;
    // A unit square in z = 0 facing +z (counter-clockwise seen from +z).
    s.add_mesh({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, {0, 1, 2, 0, 2, 3});
    const double mirror[12] = {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 2};           // x -> -x, z + 2
    const double stretch[12] = {3, 0, 0, 5, 0, 0.5, 0, 0, 0, 0, 1, 1};         // x * 3 + 5, y / 2, z + 1
    CHECK(s.add_instance(0, mirror) == 0);
    CHECK(s.add_instance(0, stretch) == 1);
    const std::vector<Ray> rays = {Ray{{-0.5f, 0.5f, 4}, 0, {0, 0, -2}, INFINITY},  // hits the mirror copy at z = 2
                                   Ray{{6.5f, 0.25f, 4}, 0, {0, 0, -1}, INFINITY},  // the stretched one at z = 1
                                   Ray{{6.5f, 0.75f, 4}, 0, {0, 0, -1}, INFINITY}}; // past its squashed y: a miss
    const auto h = s.intersect(rays);
    CHECK(h[0].inst == 0);
    CHECK(h[0].t == 1.0f);
    CHECK(h[1].inst == 1);
    CHECK(h[1].t == 3.0f);
    CHECK(!h[2].hit());
    float n[6];
    s.hit_normals(h.data(), 2, sizeof(Hit), n, 3 * sizeof(float));
    CHECK(n[2] == -1.0f);  // the mirrored square runs clockwise seen from +z: it faces -z
    CHECK(n[5] == 1.0f);
    const auto c = s.closest_point({6.5f, 0.25f, 3.0f, 9.0f, 0.25f, 1.0f});
    CHECK(c[0].inst == 1);
    CHECK(c[0].distance == doctest::Approx(2.0f));
    CHECK(c[1].distance == doctest::Approx(1.0f));  // x beyond 8 by 1: world units, not object units (1/3)
    CHECK(c[1].point[0] == doctest::Approx(8.0f));
}
