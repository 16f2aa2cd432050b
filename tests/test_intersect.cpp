// Scalar ray/triangle and ray/box kernels on the stiff cases: edges, vertices, axis-parallel rays
// with +0/-0 components, inactive and NaN rays, degenerate triangles.
#include "simd/ray_box.h"
#include "simd/packet_bounds.h"
#include "simd/ray_triangle.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

using arbor::simd::Vec3f;
using arbor::simd::woop_shear;
using arbor::simd::woop_test;

namespace {
const Vec3f v0{0, 0, 0}, v1{1, 0, 0}, v2{0, 1, 0};
constexpr float inf = std::numeric_limits<float>::infinity();

arbor::simd::TriHit<float> shoot(Vec3f o, Vec3f d, float tnear = 0.0f, float tfar = inf) {
    return woop_test(o, woop_shear(d), tnear, tfar, v0, v1, v2);
}
}  // namespace

TEST_CASE("triangle: interior hit gives t and barycentrics") {
    const auto h = shoot({0.25f, 0.5f, 1.0f}, {0, 0, -1});
    REQUIRE(h.hit);
    CHECK(h.t == doctest::Approx(1.0f));
    CHECK(h.u == doctest::Approx(0.25f));  // weight of v1 = x
    CHECK(h.v == doctest::Approx(0.5f));   // weight of v2 = y
}

TEST_CASE("triangle: unnormalized direction measures t in direction lengths") {
    const auto h = shoot({0.25f, 0.25f, 4.0f}, {0, 0, -2});
    REQUIRE(h.hit);
    CHECK(h.t == doctest::Approx(2.0f));
}

TEST_CASE("triangle: both facings hit") {
    CHECK(shoot({0.2f, 0.2f, 1.0f}, {0, 0, -1}).hit);
    CHECK(shoot({0.2f, 0.2f, -1.0f}, {0, 0, 1}).hit);
}

TEST_CASE("triangle: a point of an edge is hit by exactly one of the two triangles sharing it, from either side") {
    // The neighbour across each edge of (v0, v1, v2) uses that edge reversed (consistent winding).
    const Vec3f n01[3] = {v1, v0, {0.5f, -1, 0}}, n12[3] = {v2, v1, {1, 1, 0}}, n20[3] = {v0, v2, {-1, 0.5f, 0}};
    struct Case {
        Vec3f p;
        const Vec3f* other;
    };
    for (const Case& c : {Case{{0.5f, 0, 0}, n01}, Case{{0.25f, 0, 0}, n01}, Case{{0.5f, 0.5f, 0}, n12},
                          Case{{0.75f, 0.25f, 0}, n12}, Case{{0, 0.5f, 0}, n20}, Case{{0, 0.125f, 0}, n20}})
        for (const Vec3f d : {Vec3f{0, 0, -1}, Vec3f{0, 0, 1}, Vec3f{0.25f, 0.5f, -1}, Vec3f{-0.5f, 0.25f, 2}}) {
            const auto s = woop_shear(d);
            const bool mine = woop_test(c.p - d, s, 0, inf, v0, v1, v2).hit;
            const bool theirs = woop_test(c.p - d, s, 0, inf, c.other[0], c.other[1], c.other[2]).hit;
            CAPTURE(c.p.x);
            CAPTURE(c.p.y);
            CAPTURE(d.z);
            CHECK(mine != theirs);
        }
    CHECK_FALSE(shoot({0.5f, 0.5000001f, 1.0f}, {0, 0, -1}).hit);
    CHECK_FALSE(shoot({-1e-7f, 0.5f, 1.0f}, {0, 0, -1}).hit);
}

TEST_CASE("triangle: a ray through a shared edge hits exactly one side") {
    // Two triangles sharing the diagonal of the unit square, many oblique rays through points of it.
    const Vec3f a{0, 0, 0}, b{1, 0, 0}, c{1, 1, 0}, d{0, 1, 0};
    for (int i = 1; i < 1000; ++i) {
        const float s = float(i) / 1000.0f;
        const Vec3f p{s, s, 0.0f};
        const Vec3f dir{0.123f * s - 0.05f, -0.0731f, -1.0f};
        const Vec3f o = p - dir * 3.0f;
        const auto sh = woop_shear(dir);
        const bool h1 = woop_test(o, sh, 0, inf, a, b, c).hit;
        const bool h2 = woop_test(o, sh, 0, inf, a, c, d).hit;
        CHECK(h1 != h2);
    }
}

TEST_CASE("triangle: tnear/tfar bound the hit, inactive rays miss") {
    CHECK(shoot({0.2f, 0.2f, 1.0f}, {0, 0, -1}, 0.0f, 1.0f).hit);   // t == tfar accepted
    CHECK(shoot({0.2f, 0.2f, 1.0f}, {0, 0, -1}, 1.0f, 2.0f).hit);   // t == tnear accepted
    CHECK_FALSE(shoot({0.2f, 0.2f, 1.0f}, {0, 0, -1}, 0.0f, 0.999f).hit);
    CHECK_FALSE(shoot({0.2f, 0.2f, 1.0f}, {0, 0, -1}, 1.001f, inf).hit);
    CHECK_FALSE(shoot({0.2f, 0.2f, 1.0f}, {0, 0, -1}, 2.0f, 1.0f).hit);  // tfar < tnear
}

TEST_CASE("triangle: axis-parallel rays with +0 and -0 components") {
    for (float zx : {0.0f, -0.0f})
        for (float zy : {0.0f, -0.0f}) {
            CHECK(shoot({0.3f, 0.3f, 2.0f}, {zx, zy, -1.0f}).hit);
            CHECK(shoot({0.3f, 0.3f, -2.0f}, {zx, zy, 1.0f}).hit);
            CHECK_FALSE(shoot({1.3f, 0.3f, 2.0f}, {zx, zy, -1.0f}).hit);
        }
    // A ray lying in the triangle's plane never hits (det == 0).
    CHECK_FALSE(shoot({-1.0f, 0.2f, 0.0f}, {1.0f, 0.0f, 0.0f}).hit);
}

TEST_CASE("triangle: degenerate triangles never hit") {
    const auto s = woop_shear({0, 0, -1});
    CHECK_FALSE(woop_test({0.2f, 0.2f, 1}, s, 0, inf, v0, v0, v0).hit);                 // a point
    CHECK_FALSE(woop_test({0.5f, 0.5f, 1}, s, 0, inf, v0, {1, 1, 0}, {2, 2, 0}).hit);   // collinear
}

TEST_CASE("triangle: NaN in the ray or the triangle gives a miss") {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const auto s = woop_shear({0, 0, -1});
    CHECK_FALSE(woop_test({nan, 0.2f, 1}, s, 0, inf, v0, v1, v2).hit);
    CHECK_FALSE(woop_test({0.2f, 0.2f, 1}, s, 0, inf, {nan, 0, 0}, v1, v2).hit);
    CHECK_FALSE(woop_test({0.2f, 0.2f, 1}, s, nan, inf, v0, v1, v2).hit);
}

TEST_CASE("triangle: the double-precision fallback settles a zero edge function exactly") {
    // Origins exactly above a vertex and an edge far from the origin: the float edge functions are
    // 0 there. Of the four triangles around vertex a exactly one is hit; of the two sharing edge
    // a-b exactly one; a point just outside misses.
    const Vec3f a{1e6f, 1e6f, 0}, b{1e6f + 1, 1e6f, 0}, c{1e6f, 1e6f + 1, 0}, w{1e6f - 1, 1e6f, 0}, s{1e6f, 1e6f - 1, 0};
    const auto down = woop_shear({0, 0, -1});
    const Vec3f fan[4][3] = {{a, b, c}, {a, c, w}, {a, w, s}, {a, s, b}};
    int hits = 0;
    for (const auto& t : fan) hits += woop_test({1e6f, 1e6f, 1}, down, 0, inf, t[0], t[1], t[2]).hit;
    CHECK(hits == 1);
    CHECK(woop_test({1e6f + 0.5f, 1e6f, 1}, down, 0, inf, a, b, c).hit != woop_test({1e6f + 0.5f, 1e6f, 1}, down, 0, inf, a, s, b).hit);
    CHECK_FALSE(woop_test({1e6f - 0.0625f, 1e6f + 0.5f, 1}, down, 0, inf, a, b, c).hit);
}

using arbor::simd::slab_ray;
using arbor::simd::slab_test;

TEST_CASE("box: hits, misses and the entry distance") {
    const Vec3f lo{0, 0, 0}, hi{1, 1, 1};
    float t = 0;
    CHECK(slab_test(slab_ray({-1, 0.5f, 0.5f}, {1, 0, 0}), lo, hi, 0, inf, t));
    CHECK(t == doctest::Approx(1.0f));
    CHECK_FALSE(slab_test(slab_ray({-1, 1.5f, 0.5f}, {1, 0, 0}), lo, hi, 0, inf, t));
    CHECK_FALSE(slab_test(slab_ray({-1, 0.5f, 0.5f}, {1, 0, 0}), lo, hi, 0, 0.5f, t));  // ends before the box
    CHECK(slab_test(slab_ray({0.5f, 0.5f, 0.5f}, {1, 0, 0}), lo, hi, 0, inf, t));         // starts inside
    CHECK(t == 0.0f);
}

TEST_CASE("box: rays lying in a face plane count as inside that slab, for +0 and -0") {
    const Vec3f lo{0, 0, 0}, hi{1, 1, 1};
    float t = 0;
    for (float z : {0.0f, -0.0f}) {
        CHECK(slab_test(slab_ray({-1, 1.0f, 0.5f}, {1, z, 0}), lo, hi, 0, inf, t));   // y == hi.y
        CHECK(slab_test(slab_ray({-1, 0.0f, 0.5f}, {1, z, z}), lo, hi, 0, inf, t));   // y == lo.y
        CHECK_FALSE(slab_test(slab_ray({-1, 1.0000001f, 0.5f}, {1, z, 0}), lo, hi, 0, inf, t));
        CHECK_FALSE(slab_test(slab_ray({-1, -1e-7f, 0.5f}, {1, z, 0}), lo, hi, 0, inf, t));
    }
}

TEST_CASE("box: the far plane is padded so a grazing hit is not lost") {
    // A ray that touches the box exactly at an edge (entry == exit) must be kept.
    const Vec3f lo{0, 0, 0}, hi{1, 1, 1};
    float t = 0;
    CHECK(slab_test(slab_ray({-1, -1, 0.5f}, {1, 1, 0}), lo, hi, 0, inf, t));
    CHECK(slab_test(slab_ray({2, -1, 0.5f}, {-1, 1, 0}), lo, hi, 0, inf, t));
}

TEST_CASE("box: a degenerate (flat) box is still hit") {
    float t = 0;
    CHECK(slab_test(slab_ray({0.5f, 0.5f, 2}, {0, 0, -1}), {0, 0, 0}, {1, 1, 0}, 0, inf, t));
    CHECK(t == doctest::Approx(2.0f));
}

TEST_CASE("box: flat and thin boxes behind the origin are found when tnear < 0 (found by arbor stress)") {
    using arbor::simd::slab_ray;
    using arbor::simd::slab_test;
    // The ray of extreme-rays ray 66: it meets the flat box z = -3 at t = -8.98. With Ize's padded
    // far distance alone, the negative exit moved in front of the entry and the box was skipped.
    const Vec3f o{0.798787773f, -0.638522863f, -0.889555931f}, d{-0.174696937f, 0.209630713f, 0.234888986f};
    const auto r = slab_ray(o, d);
    float t = 0.0f;
    CHECK(slab_test(r, {-3, -3, -3}, {3, -2.5f, -3}, -inf, inf, t));
    CHECK(t == doctest::Approx(-8.98486f));
    // Many flat and thin boxes at random distances behind random origins, all containing a point of the ray.
    int lost = 0;
    for (int i = 1; i <= 2000; ++i) {
        const float s = -float(i) * 0.37f;
        const Vec3f oi{0.1f * float(i % 17), -0.05f * float(i % 11), 0.3f};
        const Vec3f di{0.3f + 0.001f * float(i % 7), -0.7f, 0.2f + 0.01f * float(i % 5)};
        const Vec3f p = oi + di * s;
        for (int axis = 0; axis < 3; ++axis) {
            Vec3f lo = p - Vec3f{1, 1, 1}, hi = p + Vec3f{1, 1, 1};
            lo[axis] = hi[axis] = p[axis];  // flat in one axis, through p
            lost += !slab_test(slab_ray(oi, di), lo, hi, -inf, inf, t);
        }
    }
    CHECK(lost == 0);
    // Boxes behind the origin are still culled for rays that start at tnear = 0.
    CHECK_FALSE(slab_test(r, {-3, -3, -3}, {3, -2.5f, -3}, 0.0f, inf, t));
}

TEST_CASE("triangle: a t beyond float range is a miss, never a hit at t = +-inf (found by arbor's fuzzer)") {
    // The crossing is at t = 1e40 (a far triangle for a short direction), or the shear overflows
    // (a denormal direction): +inf is the miss record's t, so neither may be reported as a hit.
    CHECK_FALSE(shoot({0.25f, 0.25f, 1e10f}, {0, 0, -1e-30f}).hit);
    CHECK_FALSE(shoot({0.25f, 0.25f, 1.0f}, {0, 0, -1e-40f}).hit);
    CHECK_FALSE(shoot({0.25f, 0.25f, -1e10f}, {0, 0, -1e-30f}, -inf, inf).hit);  // behind, at t = -1e40
    CHECK(shoot({0.25f, 0.25f, 1e10f}, {0, 0, -1e-20f}).hit);                     // t = 1e30 is fine
}

TEST_CASE("box: a direction component too small for its reciprocal never culls (found by arbor's fuzzer)") {
    using arbor::simd::slab_ray;
    using arbor::simd::slab_test;
    // Fuzzer ray: z moves by 9e-44 per unit t, 1/d_z overflows. At t = 9.3e18 the ray is inside the
    // box z in [0, 0.5] (it enters that slab at t = 3), so the box must not be culled.
    const Vec3f o{-0x1.ae0p-56f, -2.63444e-43f, -2.67648e-43f}, d{2.31831e-41f, -1.16891e-19f, 8.96831e-44f};
    float t = 0.0f;
    CHECK(slab_test(slab_ray(o, d), {-0.54f, -1.1f, 0.0f}, {0.0f, -0.8f, 0.5f}, 0.0f, inf, t));
    using arbor::simd::slab_rcp;
    CHECK(std::isnan(slab_rcp(1e-44f, 1.0f)));     // shear d/dmax denormal: imprecise in the triangle test
    CHECK(std::isnan(slab_rcp(1e-44f, 1e-44f)));   // 1/d overflows
    CHECK(std::isnan(slab_rcp(1e-30f, 1e10f)));
    CHECK(slab_rcp(1e-30f, 1e30f) == inf);         // shear underflows to 0: the triangle test sees no motion
    CHECK(slab_rcp(-3.7e-39f, 1e8f) == -inf);
    CHECK(slab_rcp(-0.0f, 1.0f) == -inf);          // the zero-direction rule is unchanged
    CHECK(slab_rcp(4.0f, 4.0f) == 0.25f);
    CHECK(slab_rcp(-2.0f, 1e30f) == -0.5f);
    // The batch form equals the scalar form lane by lane.
    using B = xsimd::batch<float>;
    const float ds[] = {1e-44f, -1e-44f, 1e-30f, -3.7e-39f, 0.0f, -0.0f, 4.0f, -2.0f, 1e-20f, 3e-39f, 1.0f, -7.0f, 2e-45f, 5.0f, 1e-38f, 6.0f};
    const float ms[] = {1.0f, 1e-44f, 1e30f, 1e8f, 1.0f, 1.0f, 4.0f, 1e30f, 1e19f, 3e-39f, 1.0f, 7.0f, 1.0f, 5.0f, 1e-8f, 6.0f};
    for (std::size_t i = 0; i + B::size <= 16; i += B::size) {
        alignas(64) float out[B::size];
        slab_rcp(B::load_unaligned(ds + i), B::load_unaligned(ms + i)).store_aligned(out);
        for (std::size_t l = 0; l < B::size; ++l) {
            const float ref = slab_rcp(ds[i + l], ms[i + l]);
            CAPTURE(ds[i + l]);
            CHECK((std::isnan(ref) ? std::isnan(out[l]) : out[l] == ref));
        }
    }
    // The fuzzer's second ray: its y shear underflows (the triangle test sees y = o.y throughout),
    // while 1/d.y is finite; the box of the triangle it hits must not be culled on y.
    const Vec3f o2{-1.51994e+14f, 6.76701e-41f, 6.86973e-41f}, d2{-1.07608e+08f, 3.7876e-39f, 0.0f};
    CHECK(slab_test(slab_ray(o2, d2), {-0.92f, 0.0f, 0.0f}, {-0.82f, 0.54f, 0.51f}, -1.0774e+08f, 2.53466e-38f, t));
    // A zero component still culls boxes beside the ray.
    CHECK_FALSE(slab_test(slab_ray(o, {2.3e-41f, -1.0f, 0.0f}), {-0.54f, -1.1f, 0.0f}, {0.0f, -0.8f, 0.5f}, 0.0f, inf, t));
}

TEST_CASE("box: a direction component above 2^126 (denormal reciprocal) stays conservative (found by arbor's fuzzer)") {
    using arbor::simd::slab_far;
    using arbor::simd::slab_rcp;
    // Directions from 2^125 to FLT_MAX, both signs: 1/d crosses into the denormals at 2^126.
    std::vector<float> ds;
    for (float d = 0x1p125f; d < 3.4e38f; d = std::nextafter(d * 1.0001f, INFINITY)) ds.push_back(d);
    ds.push_back(std::numeric_limits<float>::max());
    ds.push_back(0x1p126f);
    ds.push_back(std::nextafter(0x1p126f, 0.0f));
    ds.push_back(std::nextafter(0x1p126f, INFINITY));
    for (float d : std::vector<float>(ds)) ds.push_back(-d);
    std::size_t denormal = 0;
    std::vector<float> near_magnitudes;
    for (const float d : ds) {
        CAPTURE(d);
        const float rn = slab_rcp(d, std::fabs(d)), rf = slab_far(rn);
        const double exact = 1.0 / double(d);
        REQUIRE(std::isfinite(rn));
        CHECK(std::signbit(rn) == std::signbit(d));
        // Padded above 1/d by at least 1.5 ulps of the denormals (2^-149), as on a normal axis
        // (half an ulp of rounding, two of padding); a denormal one shrunk below 1/d by as much.
        CHECK(std::fabs(double(rf)) >= std::fabs(exact) + 1.5 * 0x1p-149);
        if (std::fabs(rn) < std::numeric_limits<float>::min()) {
            ++denormal;
            CHECK(std::fabs(exact) - std::fabs(double(rn)) >= 1.5 * 0x1p-149);
        }
        if (d > 0.0f) near_magnitudes.push_back(rn);
    }
    CHECK(denormal > 100);
    // slab_far is monotone on slab_rcp's values (packet_bounds.h takes it of the lanes' min and max).
    std::sort(near_magnitudes.begin(), near_magnitudes.end());
    for (std::size_t i = 1; i < near_magnitudes.size(); ++i)
        CHECK(slab_far(near_magnitudes[i - 1]) <= slab_far(near_magnitudes[i]));
    // The batch forms equal the scalar forms lane by lane.
    using B = xsimd::batch<float>;
    for (std::size_t i = 0; i + B::size <= ds.size(); i += B::size) {
        alignas(64) float dl[B::size], ml[B::size], rn[B::size], rf[B::size];
        for (std::size_t l = 0; l < B::size; ++l) dl[l] = ds[i + l], ml[l] = std::fabs(ds[i + l]);
        const B r = slab_rcp(B::load_aligned(dl), B::load_aligned(ml));
        r.store_aligned(rn);
        slab_far(r).store_aligned(rf);
        for (std::size_t l = 0; l < B::size; ++l) {
            CAPTURE(dl[l]);
            CHECK(rn[l] == slab_rcp(dl[l], ml[l]));
            CHECK(rf[l] == slab_far(slab_rcp(dl[l], ml[l])));
        }
    }
    // The fuzzer's ray (tests/fuzz/regressions/obj/huge-direction-grazing-flat-box.obj): a box flat
    // in x that the ray enters on z where it crosses the x plane. Its entry on z must not come out
    // beyond its exit on x.
    const Vec3f o{0x1.507c7ap+80f, -0x1.30fb4ap+1f, 0x1.b4a6c4p+127f}, d{-0x1.507c7ap+80f, 0x1.30fb5p+1f, -0x1.b4a6c4p+127f};
    const auto r = arbor::simd::slab_ray(o, d);
    CHECK(std::fabs(r.rcp_near.z) < std::numeric_limits<float>::min());
    int culled = 0;
    for (int i = 0; i < 2000; ++i) {
        const double t = 1.0 + i * 1e-7;  // points along the ray, as exactly as a double can
        const float px = float(double(o.x) + t * double(d.x)), pz = float(double(o.z) + t * double(d.z));
        // The box [px, px] x [-10, 10] x [pz, pz + |pz|]: the ray's entry on z is ~t, its exit on x ~t.
        float te = 0.0f;
        const bool hit = arbor::simd::slab_test(r, {px, -10.0f, std::min(pz, pz * 2.0f)}, {px, 10.0f, std::max(pz, pz * 2.0f)},
                                                0.0f, inf, te);
        culled += hit ? 0 : 1;
    }
    CHECK(culled == 0);
}

TEST_CASE("box: packet bounds leave out an axis on which a lane's reciprocal is NaN (found by arbor's fuzzer)") {
    // Lane 0 moves along x by 3.7e-43 per unit t (slab_rcp gives NaN: x never culls for it); lane 1
    // is an ordinary ray. The interval bounds must not cull the box lane 0's own slab test hits.
    struct R {
        Vec3f org;
        float tnear;
        Vec3f dir;
        float tfar;
    };
    const std::vector<R> rays = {{{0.399994f, 0.2f, 5}, 0, {3.72745e-43f, 0, -1}, inf}, {{0.5f, 0.148242f, 5}, 0, {0.05f, -0.02f, -1}, inf}};
    using P = xsimd::batch<float>;
    const auto p = arbor::simd::load_packet<P>(std::span<const R>(rays));
    const Vec3f lo{0.0f, -0.337748f, 0.801694f}, hi{0.546487f, 0.30622f, 1.02815f};
    float t = 0.0f;
    REQUIRE(arbor::simd::slab_test(arbor::simd::slab_ray(rays[0].org, rays[0].dir), lo, hi, 0.0f, inf, t));
    const auto b = arbor::simd::packet_bounds(p, p.active);
    CHECK((b.axes & 1u) == 0);
    CHECK(arbor::simd::bounds_boxes<float>(b, inf, lo, hi));
}
