// The packet and wide kernels lane by lane against the scalar instantiation (T = float) and the
// scalar oracles (slab_test with slab_ray, woop_test with woop_shear): masks bit for bit, and t,
// u, v bit for bit wherever a lane hits. Inputs: random, edges and vertices, axis-parallel rays
// with +-0, origins in box face planes, NaN/Inf and inactive lanes, partial packets, the
// double-precision fallback.
#include "simd/box_kernels.h"
#include "simd/tri_kernels.h"
#include "simd_cases.h"

#include <ostream>
#include <span>

using namespace arbor::simd;
using arbor::accel::ray_is_traceable;
using arbor::testing::bits_of;
using arbor::testing::Mismatches;
using arbor::testing::Ray;

namespace {

struct Box {
    Vec3f lo, hi;
};
struct Tri {
    Vec3f v0, v1, v2;
};

/// Boxes with faces and corners at the targets of stiff_rays: unit and half boxes, flat boxes,
/// a point box, a box far away, random boxes.
std::vector<Box> stiff_boxes(std::uint32_t seed) {
    std::vector<Box> b{{{-1, -1, -1}, {1, 1, 1}},   {{0, 0, 0}, {1, 1, 1}},      {{-1, 0.5f, 0}, {0, 1, 1}},
                       {{0, 0, 0}, {1, 1, 0}},      {{0.25f, -1, 1}, {0.25f, 1, 1}}, {{0, 0, 0}, {0, 0, 0}},
                       {{1e6f, 1e6f, 1e6f}, {1e6f + 1, 1e6f + 1, 1e6f + 1}}};
    std::mt19937 rng(seed);
    for (int i = 0; i < 25; ++i) {
        const Vec3f a = arbor::testing::uniform3(rng, -1.5f, 1.5f), c = arbor::testing::uniform3(rng, -1.5f, 1.5f);
        b.push_back({vmin(a, c), vmax(a, c)});
    }
    return b;
}

/// A closed octahedron (shared edges and vertices), slivers, degenerate and NaN triangles, a
/// triangle far from the origin (where the double fallback triggers) and random triangles.
std::vector<Tri> stiff_triangles(std::uint32_t seed) {
    const Vec3f px{1, 0, 0}, nx{-1, 0, 0}, py{0, 1, 0}, ny{0, -1, 0}, pz{0, 0, 1}, nz{0, 0, -1};
    std::vector<Tri> t{{px, py, pz}, {py, nx, pz}, {nx, ny, pz}, {ny, px, pz},
                       {py, px, nz}, {nx, py, nz}, {ny, nx, nz}, {px, ny, nz},
                       {{0, 0, 0}, {1, 1, 1}, {0.5f, 0.5f, 0.5f}},             // collinear
                       {{0.25f, -1, 1}, {0.25f, -1, 1}, {0.25f, -1, 1}},       // a point
                       {{0, 0, 0.5f}, {1, 0, 0.5f}, {1, 1e-7f, 0.5f}},         // sliver
                       {{NAN, 0, 0}, {1, 0, 0}, {0, 1, 0}},
                       {{1e6f, 1e6f, 0}, {1e6f + 1, 1e6f, 0}, {1e6f, 1e6f + 1, 0}}};
    std::mt19937 rng(seed);
    for (int i = 0; i < 19; ++i)
        t.push_back({arbor::testing::uniform3(rng, -1, 1), arbor::testing::uniform3(rng, -1, 1),
                     arbor::testing::uniform3(rng, -1, 1)});
    return t;
}

/// Rays through the corners, edge midpoints and vertices of the geometry above, plus rays straight
/// down onto the far triangle's vertex and edge (float edge function exactly 0: double fallback).
std::vector<Ray> kernel_rays() {
    std::vector<Vec3f> targets{{0, 0, 0}, {1, 1, 1}, {-1, -1, -1}, {0.5f, 0.5f, 0}, {0.5f, 0, 0.5f}, {0, 1, 0},
                               {-1, 0.5f, 0}, {0.25f, -1, 1}, {0.5f, 0.5f, 0.5f}, {1, 0.5f, 0.5f}};
    std::vector<Ray> rays = arbor::testing::stiff_rays(21, 400, targets);
    for (float dx : {0.0f, 0.5f, 1.0f, -0.0625f}) rays.push_back({{1e6f + dx, 1e6f, 1}, 0.0f, {0, 0, -1}, INFINITY});
    rays.push_back({{1e6f + 0.5f, 1e6f + 0.5f, 1}, 0.0f, {-0.0f, 0, -1}, INFINITY});
    // Rays lying in box face planes (origin in the plane, zero component across it).
    for (float z : {0.0f, -0.0f}) {
        rays.push_back({{-2, 1, 0.5f}, 0.0f, {1, z, 0}, INFINITY});
        rays.push_back({{-2, 0, 0.5f}, 0.0f, {1, z, z}, INFINITY});
        rays.push_back({{0.5f, 0.5f, 3}, 0.0f, {z, z, -1}, INFINITY});
    }
    return rays;
}

std::span<const Ray> chunk_of(const std::vector<Ray>& rays, std::size_t s, std::size_t n) {
    return std::span<const Ray>(rays).subspan(s, std::min(n, rays.size() - s));
}

/// Which ray (index into the ray list) against which box or triangle, for mismatch messages.
struct Where {
    std::size_t ray, geom;
};
std::ostream& operator<<(std::ostream& s, const Where& w) { return s << "ray " << w.ray << " geometry " << w.geom; }

/// Compares lane i of a wide/packet result with a scalar one: mask, and t (u, v) where hit.
void compare(Mismatches& bad, const char* what, Where at, bool m, bool m_ref, float t, float t_ref) {
    if (m != m_ref) bad.add(what, at, "mask", m, "expected", m_ref);
    else if (m && bits_of(t) != bits_of(t_ref)) bad.add(what, at, "t", t, "expected", t_ref);
}
template <class T>
void compare_tri(Mismatches& bad, const char* what, Where at, std::size_t i, const TriHit<T>& h,
                 const TriHit<float>& ref) {
    compare(bad, what, at, lane(h.hit, i), ref.hit, lane(h.t, i), ref.t);
    if (ref.hit && lane(h.hit, i) &&
        (bits_of(lane(h.u, i)) != bits_of(ref.u) || bits_of(lane(h.v, i)) != bits_of(ref.v)))
        bad.add(what, at, "u/v");
}

/// The scalar oracle of one ray: brute's rule (untraceable rays miss) on the scalar woop_test.
TriHit<float> oracle_tri(const Ray& r, const Tri& t) {
    TriHit<float> h = woop_test(r.org, woop_shear(r.dir), r.tnear, r.tfar, t.v0, t.v1, t.v2);
    h.hit = h.hit && ray_is_traceable(r);
    return h;
}
/// (Against box_tfar(tfar): the far distance the box kernels cull against, ray_box.h.)
bool oracle_box(const Ray& r, const Box& b, float& t) {
    return slab_test(slab_ray(r.org, r.dir), b.lo, b.hi, r.tnear, box_tfar(r.tfar), t) && ray_is_traceable(r);
}

}  // namespace

TEST_CASE_TEMPLATE("packet_box: every lane agrees with the scalar slab test", T, float, ARBOR_TEST_BATCHES) {
    const std::vector<Ray> rays = kernel_rays();
    const std::vector<Box> boxes = stiff_boxes(3);
    Mismatches bad;
    std::size_t hits = 0;
    for (std::size_t s = 0; s < rays.size(); s += lanes<T>) {
        const auto chunk = chunk_of(rays, s, lanes<T>);
        const RayPacket<T> p = load_packet<T, Ray>(chunk);
        for (const Box& b : boxes) {
            T t;
            const Mask<T> m = packet_box(p, b.lo, b.hi, t);
            for (std::size_t i = 0; i < lanes<T>; ++i) {
                if (i >= chunk.size()) {
                    if (lane(m, i)) bad.add("padding lane hit", i);
                    continue;
                }
                float t_ref = 0, t1 = 0;
                const bool m_ref = oracle_box(chunk[i], b, t_ref);
                const bool m1 = packet_box(load_packet<float, Ray>(chunk.subspan(i, 1)), b.lo, b.hi, t1);
                const Where at{s + i, std::size_t(&b - boxes.data())};
                compare(bad, "scalar instantiation", at, m1, m_ref, t1, t_ref);
                compare(bad, "packet", at, lane(m, i), m_ref, lane(t, i), t_ref);
                hits += m_ref;
            }
        }
    }
    ARBOR_CHECK_NONE(bad);
    CHECK(hits > rays.size());  // not a vacuous comparison
}

namespace {
/// WideRay::plain's rule on one ray, written out.
bool plain_ray(const Ray& r) {
    const SlabRay s = slab_ray(r.org, r.dir);
    bool plain = ray_is_traceable(r) && r.tnear >= 0.0f;
    for (int k = 0; k < 3; ++k) plain = plain && std::isfinite(s.rcp_far[k]) && std::fabs(s.rcp_near[k]) >= FLT_MIN;
    return plain;
}
}  // namespace

TEST_CASE_TEMPLATE("packet_box_plain: on packets marked plain, every lane agrees with the scalar slab test", T, float,
                   ARBOR_TEST_BATCHES) {
    const std::vector<Ray> all = kernel_rays();
    const std::vector<Box> boxes = stiff_boxes(3);
    Mismatches bad;
    // The flag: set exactly when every ray of the packet is plain (mixed packets of kernel_rays).
    std::size_t mixed = 0;
    for (std::size_t s = 0; s < all.size(); s += lanes<T>) {
        const auto chunk = chunk_of(all, s, lanes<T>);
        bool expect = true;
        for (const Ray& r : chunk) expect = expect && (plain_ray(r) || !ray_is_traceable(r));
        mixed += !expect;
        if (load_packet<T, Ray>(chunk).plain != expect) bad.add("plain flag", s, "expected", expect);
    }
    std::vector<Ray> rays;
    for (const Ray& r : all)
        if (plain_ray(r)) rays.push_back(r);
    std::size_t hits = 0, misses = 0;
    for (std::size_t s = 0; s < rays.size(); s += lanes<T>) {
        const auto chunk = chunk_of(rays, s, lanes<T>);
        const RayPacket<T> p = load_packet<T, Ray>(chunk);
        if (!p.plain) bad.add("packet of plain rays not plain", s);
        for (const Box& b : boxes) {
            T t;
            const Mask<T> m = packet_box_plain(p, b.lo, b.hi, t);
            for (std::size_t i = 0; i < lanes<T>; ++i) {
                if (i >= chunk.size()) {
                    if (lane(m, i)) bad.add("padding lane hit", i);
                    continue;
                }
                float t_ref = 0;
                const bool m_ref = oracle_box(chunk[i], b, t_ref);
                const Where at{s + i, std::size_t(&b - boxes.data())};
                // Equal as numbers: the tree of folds may give -0 where the chain gives +0.
                if (lane(m, i) != m_ref) bad.add("plain packet", at, "mask", lane(m, i), "expected", m_ref);
                else if (m_ref && !(lane(t, i) == t_ref)) bad.add("plain packet", at, "t", lane(t, i), "expected", t_ref);
                (m_ref ? hits : misses) += 1;
            }
        }
    }
    ARBOR_CHECK_NONE(bad);
    CHECK(rays.size() > 100);
    CHECK(rays.size() < all.size());
    if (lanes<T> > 1) CHECK(mixed > 0);
    CHECK(hits > rays.size());
    CHECK(misses > rays.size());
}

TEST_CASE_TEMPLATE("ray_boxes: one ray against a wide node agrees with the scalar slab test per child", T, float,
                   ARBOR_TEST_BATCHES) {
    constexpr std::size_t n = lanes<T>;
    const std::vector<Ray> rays = kernel_rays();
    const std::vector<Box> boxes = stiff_boxes(4);
    std::vector<BoxesSoA<n>> nodes((boxes.size() + n - 1) / n);
    for (std::size_t j = 0; j < nodes.size() * n; ++j) {
        if (j < boxes.size()) nodes[j / n].set(j % n, boxes[j].lo, boxes[j].hi);
        else nodes[j / n].set_empty(j % n);
    }
    Mismatches bad;
    std::size_t hits = 0;
    for (const Ray& r : rays) {
        const WideRay<T> w = wide_ray<T>(r.org, r.dir, r.tnear, r.tfar);
        const WideRay<float> w1 = wide_ray<float>(r.org, r.dir, r.tnear, r.tfar);
        for (std::size_t node = 0; node < nodes.size(); ++node) {
            T t;
            const Mask<T> m = ray_boxes(w, nodes[node], t);
            for (std::size_t i = 0; i < n; ++i) {
                const std::size_t j = node * n + i;
                if (j >= boxes.size()) {
                    if (lane(m, i)) bad.add("empty slot hit", j);
                    continue;
                }
                float t_ref = 0, t1 = 0;
                const bool m_ref = oracle_box(r, boxes[j], t_ref);
                BoxesSoA<1> one;
                one.set(0, boxes[j].lo, boxes[j].hi);
                const Where at{std::size_t(&r - rays.data()), j};
                const bool m1 = ray_boxes(w1, one, t1);
                compare(bad, "scalar instantiation", at, m1, m_ref, t1, t_ref);
                compare(bad, "wide", at, lane(m, i), m_ref, lane(t, i), t_ref);
                hits += m_ref;
            }
        }
    }
    ARBOR_CHECK_NONE(bad);
    CHECK(hits > rays.size());
}

TEST_CASE_TEMPLATE("ray_boxes_plain: on rays marked plain, the same hits and entry distances as the scalar slab test", T,
                   float, ARBOR_TEST_BATCHES) {
    constexpr std::size_t n = lanes<T>;
    const std::vector<Ray> rays = kernel_rays();
    const std::vector<Box> boxes = stiff_boxes(4);
    std::vector<BoxesSoA<n>> nodes((boxes.size() + n - 1) / n);
    for (std::size_t j = 0; j < nodes.size() * n; ++j) {
        if (j < boxes.size()) nodes[j / n].set(j % n, boxes[j].lo, boxes[j].hi);
        else nodes[j / n].set_empty(j % n);
    }
    Mismatches bad;
    std::size_t plain = 0, not_plain = 0, hits = 0, misses = 0;
    for (const Ray& r : rays) {
        const WideRay<T> w = wide_ray<T>(r.org, r.dir, r.tnear, r.tfar);
        const bool expect = plain_ray(r);
        if (w.plain != expect) bad.add("plain flag", std::size_t(&r - rays.data()), "is", w.plain, "expected", expect);
        if (!w.plain) {
            ++not_plain;
            continue;
        }
        ++plain;
        for (std::size_t node = 0; node < nodes.size(); ++node) {
            T t;
            const Mask<T> m = ray_boxes_plain(w, &nodes[node].b[0][0][0], t);
            for (std::size_t i = 0; i < n; ++i) {
                const std::size_t j = node * n + i;
                if (j >= boxes.size()) {
                    if (lane(m, i)) bad.add("empty slot hit", j);
                    continue;
                }
                float t_ref = 0;
                const bool m_ref = oracle_box(r, boxes[j], t_ref);
                const Where at{std::size_t(&r - rays.data()), j};
                // Equal as numbers: the tree of folds may give -0 where the chain gives +0.
                if (lane(m, i) != m_ref) bad.add("plain", at, "mask", lane(m, i), "expected", m_ref);
                else if (m_ref && !(lane(t, i) == t_ref)) bad.add("plain", at, "t", lane(t, i), "expected", t_ref);
                (m_ref ? hits : misses) += 1;
            }
        }
    }
    ARBOR_CHECK_NONE(bad);
    CHECK(plain > 100);      // the fast form is exercised...
    CHECK(not_plain > 10);   // ...and the rays it must not take (axis-parallel, tnear < 0, ...) exist
    CHECK(hits > plain);
    CHECK(misses > plain);
}

TEST_CASE("box kernels: empty slots never hit, even for axis-parallel rays with +-0") {
    BoxesSoA<1> empty;
    empty.set_empty(0);
    for (const Vec3f& d : {Vec3f{0, 0, 1}, Vec3f{-0.0f, 0, -1}, Vec3f{1, -0.0f, 0}, Vec3f{0.3f, -0.2f, 0.1f}}) {
        float t = 0;
        CHECK_FALSE(ray_boxes(wide_ray<float>({0, 0, 0}, d, 0.0f, INFINITY), empty, t));
        CHECK_FALSE(ray_boxes(wide_ray<float>({0, 0, 0}, d, -INFINITY, INFINITY), empty, t));
    }
}

namespace {
template <class T, bool PerLane> void check_packet_triangles() {
    const std::vector<Ray> rays = kernel_rays();
    const std::vector<Tri> tris = stiff_triangles(5);
    Mismatches bad;
    std::size_t hits = 0, fallback_hits = 0;
    for (std::size_t s = 0; s < rays.size(); s += lanes<T>) {
        const auto chunk = chunk_of(rays, s, lanes<T>);
        const RayPacket<T> p = load_packet<T, Ray>(chunk);
        for (const Tri& tri : tris) {
            const TriHit<T> h = PerLane ? packet_triangle_lanes(p, tri.v0, tri.v1, tri.v2)
                                        : packet_triangle(p, tri.v0, tri.v1, tri.v2);
            for (std::size_t i = 0; i < lanes<T>; ++i) {
                if (i >= chunk.size()) {
                    if (lane(h.hit, i)) bad.add("padding lane hit", i);
                    continue;
                }
                const TriHit<float> ref = oracle_tri(chunk[i], tri);
                const RayPacket<float> p1 = load_packet<float, Ray>(chunk.subspan(i, 1));
                const Where at{s + i, std::size_t(&tri - tris.data())};
                compare_tri(bad, "scalar instantiation", at, 0, packet_triangle_lanes(p1, tri.v0, tri.v1, tri.v2), ref);
                compare_tri(bad, "scalar uniform", at, 0, packet_triangle(p1, tri.v0, tri.v1, tri.v2), ref);
                compare_tri(bad, "packet", at, i, h, ref);
                hits += ref.hit;
                fallback_hits += ref.hit && tri.v0.x == 1e6f;
            }
        }
    }
    ARBOR_CHECK_NONE(bad);
    CHECK(hits > rays.size() / 2);
    // Rays exactly through the far triangle's vertices and edges (zero edge functions settled in
    // double): the tie rule gives it some of them, the lone triangle's other side the rest.
    CHECK(fallback_hits >= 2);
}
}  // namespace

TEST_CASE_TEMPLATE("packet_triangle: every lane agrees bit for bit with the scalar watertight test", T, float,
                   ARBOR_TEST_BATCHES) {
    SUBCASE("per-lane permutation by selects") { check_packet_triangles<T, true>(); }
    SUBCASE("uniform fast path when the lanes allow it") { check_packet_triangles<T, false>(); }
}

TEST_CASE_TEMPLATE("packet_triangle: a coherent packet takes the uniform path with identical results", T,
                   ARBOR_TEST_BATCHES) {
    std::vector<Ray> rays;
    for (std::size_t i = 0; i < lanes<T>; ++i)
        rays.push_back({{0.1f * float(i % 4), 0.1f * float(i / 4), 2}, 0.0f, {0.01f, -0.02f, -1}, INFINITY});
    const RayPacket<T> p = load_packet<T, Ray>(std::span<const Ray>(rays));
    REQUIRE(p.woop.uniform);
    const TriHit<T> a = packet_triangle(p, {-0.1f, -0.1f, 0}, {1, 0, 0}, {0, 1, 0});
    const TriHit<T> b = packet_triangle_lanes(p, {-0.1f, -0.1f, 0}, {1, 0, 0}, {0, 1, 0});
    CHECK(to_bits(a.hit) == to_bits(b.hit));
    CHECK(to_bits(a.hit) != 0u);
    for (std::size_t i = 0; i < lanes<T>; ++i)
        if (lane(a.hit, i)) CHECK((bits_of(lane(a.t, i)) == bits_of(lane(b.t, i)) &&
                                   bits_of(lane(a.u, i)) == bits_of(lane(b.u, i))));
}

TEST_CASE_TEMPLATE("ray_triangles: one ray against a triangle block agrees bit for bit per triangle", T, float,
                   ARBOR_TEST_BATCHES) {
    constexpr std::size_t n = lanes<T>;
    const std::vector<Ray> rays = kernel_rays();
    const std::vector<Tri> tris = stiff_triangles(6);
    std::vector<TrisSoA<n>> blocks((tris.size() + n - 1) / n);
    for (std::size_t j = 0; j < blocks.size() * n; ++j) {
        if (j < tris.size()) blocks[j / n].set(j % n, tris[j].v0, tris[j].v1, tris[j].v2);
        else blocks[j / n].set_empty(j % n);
    }
    Mismatches bad;
    std::size_t hits = 0;
    for (const Ray& r : rays) {
        const WideRay<T> w = wide_ray<T>(r.org, r.dir, r.tnear, r.tfar);
        const WideRay<float> w1 = wide_ray<float>(r.org, r.dir, r.tnear, r.tfar);
        for (std::size_t blk = 0; blk < blocks.size(); ++blk) {
            const TriHit<T> h = ray_triangles(w, blocks[blk]);
            const TriHit<T> hr = ray_triangles(w, Vec3<T>{load_lanes<T>(blocks[blk].v[0][0]), load_lanes<T>(blocks[blk].v[0][1]),
                                                          load_lanes<T>(blocks[blk].v[0][2])},
                                               Vec3<T>{load_lanes<T>(blocks[blk].v[1][0]), load_lanes<T>(blocks[blk].v[1][1]),
                                                       load_lanes<T>(blocks[blk].v[1][2])},
                                               Vec3<T>{load_lanes<T>(blocks[blk].v[2][0]), load_lanes<T>(blocks[blk].v[2][1]),
                                                       load_lanes<T>(blocks[blk].v[2][2])});
            for (std::size_t i = 0; i < n; ++i) {
                const std::size_t j = blk * n + i;
                if (j >= tris.size()) {
                    if (lane(h.hit, i)) bad.add("empty slot hit", j);
                    continue;
                }
                const TriHit<float> ref = oracle_tri(r, tris[j]);
                TrisSoA<1> one;
                one.set(0, tris[j].v0, tris[j].v1, tris[j].v2);
                const Where at{std::size_t(&r - rays.data()), j};
                compare_tri(bad, "scalar instantiation", at, 0, ray_triangles(w1, one), ref);
                compare_tri(bad, "scalar instantiation, early out", at, 0, ray_triangles<float, true>(w1, &one.v[0][0][0]), ref);
                compare_tri(bad, "wide", at, i, h, ref);
                compare_tri(bad, "wide registers", at, i, hr, ref);
                compare_tri(bad, "wide, early out", at, i, ray_triangles<T, true>(w, &blocks[blk].v[0][0][0]), ref);
                hits += ref.hit;
            }
        }
    }
    ARBOR_CHECK_NONE(bad);
    CHECK(hits > rays.size() / 2);
}

TEST_CASE_TEMPLATE("ray_triangles: rays through the shared edges and vertices of a closed mesh never leak", T,
                   ARBOR_TEST_BATCHES) {
    // The octahedron's 8 faces in one or more blocks; rays from its centre through edge points and
    // vertices must hit at least one face (watertightness survives the SIMD form).
    constexpr std::size_t n = lanes<T>;
    const std::vector<Tri> tris = stiff_triangles(7);
    std::vector<TrisSoA<n>> blocks((8 + n - 1) / n);
    for (std::size_t j = 0; j < blocks.size() * n; ++j) {
        if (j < 8) blocks[j / n].set(j % n, tris[j].v0, tris[j].v1, tris[j].v2);
        else blocks[j / n].set_empty(j % n);
    }
    std::mt19937 rng(9);
    std::size_t leaks = 0;
    for (int i = 0; i < 2000; ++i) {
        const Tri& f = tris[std::size_t(i) % 8];
        const float s = arbor::testing::uniform(rng, 0.0f, 1.0f);
        const Vec3f through = (i % 3 == 0) ? f.v0 : f.v0 + (f.v1 - f.v0) * s;  // a vertex or an edge point
        const Vec3f o = arbor::testing::uniform3(rng, -0.2f, 0.2f);
        const WideRay<T> w = wide_ray<T>(o, through - o, 0.0f, INFINITY);
        bool hit = false;
        for (const auto& blk : blocks) hit = hit || any(ray_triangles(w, blk).hit);
        leaks += !hit;
    }
    CHECK(leaks == 0);
}
