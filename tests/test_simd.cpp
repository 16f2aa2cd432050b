// simd/ building blocks lane by lane against their scalar forms: mask conversions, sign bits,
// the padded reciprocal, reductions, hit ordering, and RayPacket loading/storing.
#include "simd/lane_order.h"
#include "simd/ray_packet.h"
#include "simd/wide_ray.h"
#include "simd_cases.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <numeric>
#include <span>

using namespace arbor::simd;
using arbor::testing::bits_of;
using arbor::testing::Mismatches;
using arbor::testing::Ray;

namespace {

/// Special values plus random bit patterns (every class of float: denormals, NaNs, infinities).
std::vector<float> special_floats() {
    std::vector<float> v{0.0f,     -0.0f,     FLT_TRUE_MIN, -FLT_TRUE_MIN, FLT_MIN,   -FLT_MIN,
                         std::nextafter(FLT_MIN, 0.0f),     1.0f,          -1.0f,     FLT_MAX,
                         -FLT_MAX, std::nextafter(FLT_MAX, 0.0f), INFINITY,  -INFINITY, NAN, -NAN, 3.0e-39f, 1e30f};
    std::mt19937 rng(7);
    for (int i = 0; i < 4000; ++i) v.push_back(std::bit_cast<float>(std::uint32_t(rng())));
    while (v.size() % 16) v.push_back(0.5f);
    return v;
}

bool same_float(float a, float b) { return (std::isnan(a) && std::isnan(b)) || bits_of(a) == bits_of(b); }

}  // namespace

TEST_CASE_TEMPLATE("simd: to_bits, from_bits and first_lanes agree", T, ARBOR_TEST_BATCHES) {
    constexpr std::size_t n = lanes<T>;
    const std::uint32_t all_lanes = n == 32 ? ~0u : (1u << n) - 1u;
    std::mt19937 rng(1);
    for (int i = 0; i < 200; ++i) {
        const std::uint32_t b = std::uint32_t(rng()) & all_lanes;
        const Mask<T> m = from_bits<T>(b);
        REQUIRE(to_bits(m) == b);
        for (std::size_t k = 0; k < n; ++k) CHECK(lane(m, k) == bool((b >> k) & 1u));
    }
    for (std::size_t count = 0; count <= n + 1; ++count)
        CHECK(to_bits(first_lanes<T>(count)) == (count >= n ? all_lanes : (1u << count) - 1u));
    CHECK(to_bits(first_lanes<float>(0)) == 0u);
    CHECK(to_bits(first_lanes<float>(3)) == 1u);
}

TEST_CASE_TEMPLATE("simd: signbit_mask, vabs and pad_2ulp match the scalar forms bit for bit", T, ARBOR_TEST_BATCHES) {
    const std::vector<float> v = special_floats();
    Mismatches bad;
    for (std::size_t s = 0; s < v.size(); s += lanes<T>) {
        const T x = load_lanes<T>(&v[s]);
        const Mask<T> sign = signbit_mask(x);
        const T a = vabs(x), pad = pad_2ulp(x);
        for (std::size_t i = 0; i < lanes<T>; ++i) {
            const float xi = v[s + i];
            if (lane(sign, i) != signbit_mask(xi)) bad.add("signbit", xi);
            if (!same_float(lane(a, i), vabs(xi))) bad.add("abs", xi);
            if (!same_float(lane(pad, i), pad_2ulp(xi))) bad.add("pad", xi, lane(pad, i), pad_2ulp(xi));
        }
    }
    ARBOR_CHECK_NONE(bad);
    // The scalar reference really moves two ulps outward, and saturates at infinity.
    CHECK(pad_2ulp(1.0f) == std::nextafter(std::nextafter(1.0f, 2.0f), 2.0f));
    CHECK(pad_2ulp(-FLT_MAX) == -INFINITY);
}

TEST_CASE_TEMPLATE("simd: rmax and rmin return b unless a is strictly larger/smaller, as the scalar forms", T,
                   ARBOR_TEST_BATCHES) {
    std::vector<float> v = special_floats();
    std::vector<float> w(v.size());
    std::mt19937 rng(17);
    for (std::size_t i = 0; i < w.size(); ++i) w[i] = (i % 3 == 0) ? v[(i * 7 + 1) % v.size()] : v[rng() % v.size()];
    for (std::size_t i = 0; i + 1 < v.size(); i += 5) w[i] = -v[i];  // +0/-0, NaN/-NaN and x/-x pairs
    Mismatches bad;
    for (std::size_t s = 0; s < v.size(); s += lanes<T>) {
        const T a = load_lanes<T>(&v[s]), b = load_lanes<T>(&w[s]);
        const T mx = rmax(a, b), mn = rmin(a, b);
        for (std::size_t i = 0; i < lanes<T>; ++i) {
            if (bits_of(lane(mx, i)) != bits_of(rmax(v[s + i], w[s + i]))) bad.add("rmax", v[s + i], w[s + i]);
            if (bits_of(lane(mn, i)) != bits_of(rmin(v[s + i], w[s + i]))) bad.add("rmin", v[s + i], w[s + i]);
        }
    }
    ARBOR_CHECK_NONE(bad);
    CHECK(bits_of(lane(rmax(T(0.0f), T(-0.0f)), 0)) == bits_of(-0.0f));
    CHECK(std::isnan(lane(rmin(T(1.0f), T(NAN)), 0)));
    CHECK(lane(rmin(T(NAN), T(1.0f)), 0) == 1.0f);
}

TEST_CASE_TEMPLATE("simd: hmin and closest_lane pick the nearest hit, lowest lane on ties", T, ARBOR_TEST_BATCHES) {
    constexpr std::size_t n = lanes<T>;
    std::mt19937 rng(3);
    const float pool[] = {-0.0f, 0.0f, 0.5f, 1.0f, 1.0f, 2.0f, INFINITY};
    Mismatches bad;
    for (int it = 0; it < 2000; ++it) {
        alignas(64) float t[n];
        for (float& x : t) x = (it % 2) ? pool[rng() % 7] : arbor::testing::uniform(rng, 0.0f, 10.0f);
        const std::uint32_t b = std::uint32_t(rng()) & (n == 32 ? ~0u : (1u << n) - 1u);
        const T tv = load_lanes<T>(t);
        int expect = -1;
        for (std::size_t i = 0; i < n; ++i)
            if (((b >> i) & 1u) && (expect < 0 || t[i] < t[expect])) expect = int(i);
        const int got = closest_lane(from_bits<T>(b), tv);
        if (got != expect) bad.add("closest", got, expect, b);
        const float m = hmin(tv), ref = *std::min_element(t, t + n);
        if (m != ref) bad.add("hmin", m, ref);
    }
    ARBOR_CHECK_NONE(bad);
    CHECK(closest_lane(false, 1.0f) == -1);
    CHECK(closest_lane(true, 1.0f) == 0);
}

TEST_CASE_TEMPLATE("simd: iselect and int_equal work lane by lane", T, ARBOR_TEST_BATCHES) {
    using I = IntOf<T>;
    alignas(64) std::int32_t a[lanes<T>], b[lanes<T>];
    for (std::size_t i = 0; i < lanes<T>; ++i) {
        a[i] = std::int32_t(i);
        b[i] = (i % 3 == 0) ? std::int32_t(i) : -1;
    }
    const I ai = load_lanes<I>(a), bi = load_lanes<I>(b);
    const Mask<T> eq = int_equal(ai, bi);
    const I sel = iselect(eq, I(100), bi);
    for (std::size_t i = 0; i < lanes<T>; ++i) {
        CHECK(lane(eq, i) == (i % 3 == 0));
        CHECK(lane(sel, i) == (i % 3 == 0 ? 100 : -1));
    }
}

TEST_CASE_TEMPLATE("simd: order_hits is a stable sort of the hit lanes by distance", T, float, ARBOR_TEST_BATCHES) {
    constexpr std::size_t n = lanes<T>;
    std::mt19937 rng(5);
    Mismatches bad;
    for (int it = 0; it < 3000; ++it) {
        alignas(64) float t[n];
        for (float& x : t) x = (it % 3 == 0) ? float(rng() % 3) : arbor::testing::uniform(rng, -1.0f, 5.0f);
        std::uint32_t b = std::uint32_t(rng()) & (n == 32 ? ~0u : (1u << n) - 1u);
        if (it % 4 == 0) b &= b - 1;  // favour small counts, as in traversal
        std::vector<std::uint8_t> expect;
        for (std::size_t i = 0; i < n; ++i)
            if ((b >> i) & 1u) expect.push_back(std::uint8_t(i));
        std::stable_sort(expect.begin(), expect.end(), [&t](std::uint8_t x, std::uint8_t y) { return t[x] < t[y]; });
        std::uint8_t out[32];
        const int count = order_hits(b, load_lanes<T>(t), out);
        if (count != int(expect.size()) || !std::equal(expect.begin(), expect.end(), out)) bad.add("order", b, count);
    }
    ARBOR_CHECK_NONE(bad);
}

namespace {
/// Lane i's Woop axes, read back from the masks.
template <class T> WoopShear axes_of(const WoopLanes<T>& w, std::size_t i) {
    const auto axis = [i](const Mask<T>& m0, const Mask<T>& m1) { return lane(m0, i) ? 0 : (lane(m1, i) ? 1 : 2); };
    WoopShear s;
    s.kx = axis(w.kx0, w.kx1);
    s.ky = axis(w.ky0, w.ky1);
    s.kz = axis(w.kz0, w.kz1);
    s.sx = lane(w.sx, i);
    s.sy = lane(w.sy, i);
    s.sz = lane(w.sz, i);
    return s;
}

/// Checks one lane of a packet against the scalar oracles (ray_is_traceable, slab_ray, woop_shear).
template <class T> void check_lane(const RayPacket<T>& p, std::size_t i, const Ray* ray, Mismatches& bad) {
    const bool active = ray && arbor::accel::ray_is_traceable(*ray);
    if (lane(p.active, i) != active) return bad.add("active", i);
    if (!active) {
        if (!(lane(p.tnear, i) == INFINITY && lane(p.tfar, i) == -INFINITY)) bad.add("inactive range", i);
        return;
    }
    const SlabRay s = slab_ray(ray->org, ray->dir);
    const WoopShear w = woop_shear(ray->dir), got = axes_of(p.woop, i);
    for (int k = 0; k < 3; ++k) {
        if (bits_of(lane(p.org[k], i)) != bits_of(ray->org[k])) bad.add("org", i, k);
        if (bits_of(lane(p.dir[k], i)) != bits_of(ray->dir[k])) bad.add("dir", i, k);
        if (bits_of(lane(p.rcp_near[k], i)) != bits_of(s.rcp_near[k])) bad.add("rcp_near", i, k);
        if (bits_of(lane(p.rcp_far[k], i)) != bits_of(s.rcp_far[k])) bad.add("rcp_far", i, k);
        if (lane(p.near_is_hi[k], i) != bool(s.near_is_hi[k])) bad.add("near_is_hi", i, k);
    }
    if (bits_of(lane(p.tnear, i)) != bits_of(ray->tnear) || bits_of(lane(p.tfar, i)) != bits_of(ray->tfar))
        bad.add("range", i);
    if (got.kx != w.kx || got.ky != w.ky || got.kz != w.kz) bad.add("woop axes", i, got.kx, got.ky, got.kz);
    if (bits_of(got.sx) != bits_of(w.sx) || bits_of(got.sy) != bits_of(w.sy) || bits_of(got.sz) != bits_of(w.sz))
        bad.add("woop shear", i);
    if (p.woop.uniform && (got.kx != p.woop.kx || got.ky != p.woop.ky || got.kz != p.woop.kz))
        bad.add("uniform but lane differs", i);
}
}  // namespace

TEST_CASE_TEMPLATE("RayPacket: every lane matches the scalar slab and Woop constants", T, float, ARBOR_TEST_BATCHES) {
    const std::vector<Vec3f> targets{{0, 0, 0}, {1, 1, 1}, {-1, 0.5f, 0}, {0.25f, -1, 1}};
    const std::vector<Ray> rays = arbor::testing::stiff_rays(11, 300, targets);
    Mismatches bad;
    std::size_t mixed = 0;
    for (std::size_t s = 0; s < rays.size(); s += lanes<T>) {
        const auto chunk = std::span<const Ray>(rays).subspan(s, std::min(lanes<T>, rays.size() - s));
        const RayPacket<T> p = load_packet<T, Ray>(chunk);
        for (std::size_t i = 0; i < lanes<T>; ++i) check_lane(p, i, i < chunk.size() ? &chunk[i] : nullptr, bad);
        mixed += !p.woop.uniform;
    }
    ARBOR_CHECK_NONE(bad);
    if constexpr (lanes<T> > 1) CHECK(mixed > 0);  // the per-lane permutation was exercised
}

TEST_CASE_TEMPLATE("slab_rcps: slab_rcp bit for bit, with and without the quotient, over every exponent", T, ARBOR_TEST_BATCHES) {
    // Packets whose directions are one scale 2^e times components in [0.5, 1] or zero (the
    // quotient-free form: every lane's q >= 2^-64), from denormal components (1/d overflows: NaN)
    // to components above 2^126 (denormal reciprocals, shrunk); and packets where each lane has
    // its own scale (near-axis directions: the full slab_rcp).
    constexpr std::size_t n = lanes<T>;
    std::mt19937 rng(29);
    std::uniform_real_distribution<float> unit(0.5f, 1.0f);
    Mismatches bad;
    std::size_t quotient_free = 0, overflow = 0, denormal = 0;
    for (int e = -150; e <= 127; ++e)
        for (int mixed = 0; mixed < 2; ++mixed) {
            alignas(64) float d[3][n], dmax[n];
            for (std::size_t i = 0; i < n; ++i) {
                const int scale = mixed ? e - int(rng() % 80) : e;
                for (int k = 0; k < 3; ++k) {
                    const float c = rng() % 5 == 0 ? 0.0f : std::ldexp(unit(rng), scale);
                    d[k][i] = rng() % 2 ? -c : c;
                }
                if (mixed && i % 3 == 0) d[int(rng() % 3)][i] = std::ldexp(1.0f, e);  // one component far above the others
                dmax[i] = std::max(std::fabs(d[0][i]), std::max(std::fabs(d[1][i]), std::fabs(d[2][i])));
            }
            const Vec3<T> got = slab_rcps(Vec3<T>{load_lanes<T>(d[0]), load_lanes<T>(d[1]), load_lanes<T>(d[2])}, load_lanes<T>(dmax));
            bool free = true;
            for (std::size_t i = 0; i < n; ++i)
                for (int k = 0; k < 3; ++k) {
                    free = free && (d[k][i] == 0.0f || std::fabs(d[k][i]) * 0x1p64f >= dmax[i]);
                    const float ref = slab_rcp(d[k][i], dmax[i]);
                    if (!same_float(lane(got[k], i), ref)) bad.add("lane", e, mixed, i, k, d[k][i], dmax[i], ref, lane(got[k], i));
                    overflow += d[k][i] != 0.0f && std::isnan(ref) && std::fabs(d[k][i]) * 0x1p64f >= dmax[i];
                    denormal += ref != 0.0f && std::fabs(ref) < FLT_MIN;
                }
            quotient_free += free;
        }
    ARBOR_CHECK_NONE(bad);
    // Both forms ran, and the quotient-free one met 1/d overflowing and denormal reciprocals.
    CHECK(quotient_free > 200);
    CHECK(quotient_free < 2 * 278);
    CHECK(overflow > 0);
    CHECK(denormal > 0);
}

TEST_CASE_TEMPLATE("RayPacket: add_woop after lanes finished gives the loaded lanes' set-up", T, float, ARBOR_TEST_BATCHES) {
    // The packet walk's order: load_packet_boxes, lanes leave p.active (an any-hit walk), then
    // add_woop with the mask as loaded. Every loaded lane must get the scalar constants, and the
    // uniform permutation must be judged over the loaded lanes, not the ones still active.
    const std::vector<Ray> rays = arbor::testing::stiff_rays(17, 300, {{0, 0, 0}, {1, -1, 0.5f}});
    Mismatches bad;
    std::size_t mixed = 0;
    for (std::size_t s = 0; s < rays.size(); s += lanes<T>) {
        const auto chunk = std::span<const Ray>(rays).subspan(s, std::min(lanes<T>, rays.size() - s));
        RayPacket<T> q = load_packet_boxes<T, Ray>(chunk);
        const Mask<T> loaded = q.active;
        const std::uint32_t bits = to_bits(loaded);
        q.active = from_bits<T>(bits & (0u - bits));  // all but the lowest loaded lane finished
        add_woop(q, loaded);
        q.active = loaded;
        for (std::size_t i = 0; i < lanes<T>; ++i) check_lane(q, i, i < chunk.size() ? &chunk[i] : nullptr, bad);
        const RayPacket<T> p = load_packet<T, Ray>(chunk);
        if (p.plain != q.plain || to_bits(p.plain_lanes) != to_bits(q.plain_lanes)) bad.add("plain", s);
        if (p.woop.uniform != q.woop.uniform || p.woop.kx != q.woop.kx || p.woop.ky != q.woop.ky || p.woop.kz != q.woop.kz)
            bad.add("uniform permutation", s);
        mixed += !q.woop.uniform;
    }
    ARBOR_CHECK_NONE(bad);
    if constexpr (lanes<T> > 1) CHECK(mixed > 0);  // lanes of other permutations than the one left active
}

TEST_CASE_TEMPLATE("store_hits: full and partial packets write every field's bits", T, float, ARBOR_TEST_BATCHES) {
    // (Float16: a full packet takes the in-register transpose, a partial one the lane loop.)
    constexpr std::size_t n = lanes<T>;
    std::mt19937 rng(41);
    const std::vector<float> special = special_floats();
    Mismatches bad;
    for (int round = 0; round < 50; ++round) {
        alignas(64) float t[n], u[n], v[n];
        alignas(64) std::int32_t prim[n];
        for (std::size_t i = 0; i < n; ++i) {
            t[i] = special[rng() % special.size()], u[i] = special[rng() % special.size()], v[i] = special[rng() % special.size()];
            prim[i] = std::int32_t(rng());
        }
        PacketHit<T> h;
        h.t = load_lanes<T>(t), h.u = load_lanes<T>(u), h.v = load_lanes<T>(v);
        h.prim = load_lanes<IntOf<T>>(prim);
        for (const std::size_t count : {n, n + 3, std::size_t(round % int(n))}) {
            std::vector<arbor::accel::Hit> out(n + 3, arbor::accel::Hit{1.5f, 77u, 2.5f, 3.5f});
            store_hits(h, std::span<arbor::accel::Hit>(out).first(count));
            for (std::size_t i = 0; i < out.size(); ++i) {
                const bool written = i < std::min(count, n);
                const arbor::accel::Hit want = written ? arbor::accel::Hit{t[i], std::uint32_t(prim[i]), u[i], v[i]}
                                                       : arbor::accel::Hit{1.5f, 77u, 2.5f, 3.5f};
                if (bits_of(out[i].t) != bits_of(want.t) || out[i].prim != want.prim || bits_of(out[i].u) != bits_of(want.u) ||
                    bits_of(out[i].v) != bits_of(want.v))
                    bad.add("record", round, count, i);
            }
        }
    }
    ARBOR_CHECK_NONE(bad);
}

TEST_CASE_TEMPLATE("RayPacket: partial packets and the uniform permutation flag", T, ARBOR_TEST_BATCHES) {
    constexpr std::size_t n = lanes<T>;
    std::vector<Ray> rays;
    for (std::size_t i = 0; i < n; ++i) rays.push_back({{0, 0, 5}, 0.0f, {0.01f * float(i), 0.02f, -1.0f}, INFINITY});
    RayPacket<T> p = load_packet<T, Ray>(std::span<const Ray>(rays));
    CHECK(to_bits(p.active) == to_bits(first_lanes<T>(n)));
    CHECK(p.woop.uniform);
    CHECK((p.woop.kx == 1 && p.woop.ky == 0 && p.woop.kz == 2));  // -z dominant: x and y swapped
    rays[n - 1].dir = {1.0f, 0.0f, 0.0f};
    CHECK_FALSE(load_packet<T, Ray>(std::span<const Ray>(rays)).woop.uniform);
    // The odd lane out is inactive: it no longer counts.
    rays[n - 1].tfar = -1.0f;
    CHECK(load_packet<T, Ray>(std::span<const Ray>(rays)).woop.uniform);
    // A partial packet: the missing lanes are inactive and never counted.
    p = load_packet<T, Ray>(std::span<const Ray>(rays).first(n / 2 + 1));
    CHECK(to_bits(p.active) == to_bits(first_lanes<T>(n / 2 + 1)));
    CHECK(p.woop.uniform);
    CHECK(to_bits(load_packet<T, Ray>(std::span<const Ray>()).active) == 0u);
}

TEST_CASE_TEMPLATE("PacketHit: record_hits keeps the tie rule (smaller t, equal t lower prim), store_hits writes Hit records", T, float,
                   ARBOR_TEST_BATCHES) {
    constexpr std::size_t n = lanes<T>;
    std::vector<Ray> rays(n, Ray{{0, 0, 5}, 0.0f, {0, 0, -1}, INFINITY});
    rays[0].tfar = -1.0f;  // inactive: never recorded
    RayPacket<T> p = load_packet<T, Ray>(std::span<const Ray>(rays));
    PacketHit<T> best;
    alignas(64) float t1[n], t2[n];
    for (std::size_t i = 0; i < n; ++i) {
        t1[i] = 2.0f + float(i);
        t2[i] = (i % 2) ? t1[i] : t1[i] - 1.0f;  // odd lanes tie, even lanes are closer
    }
    TriHit<T> h{first_lanes<T>(n), load_lanes<T>(t1), T(0.25f), T(0.5f)};
    record_hits(best, p, h, 7);
    h.t = load_lanes<T>(t2);
    h.u = T(0.125f);
    const std::uint32_t second = to_bits(record_hits(best, p, h, 9));
    // A third hit at the recorded t with a lower prim takes the lane (the tie rule), a higher one not.
    const T recorded = best.t;
    h.t = recorded;
    CHECK(to_bits(record_hits(best, p, h, 99)) == 0u);
    CHECK(to_bits(record_hits(best, p, h, 2) & p.active) == (to_bits(p.active) & ~1u));
    h.t = recorded + T(1.0f);  // farther: nothing taken
    CHECK(to_bits(record_hits(best, p, h, 1)) == 0u);
    std::vector<arbor::accel::Hit> out(n + 1);
    store_hits(best, std::span<arbor::accel::Hit>(out).first(n));
    for (std::size_t i = 0; i < n; ++i) {
        CAPTURE(i);
        if (i == 0) {
            CHECK_FALSE(out[i].is_hit());
            CHECK(out[i].t == INFINITY);
            continue;
        }
        const bool closer = i % 2 == 0;
        CHECK(bool((second >> i) & 1u) == closer);
        CHECK(out[i].prim == 2u);  // the tie at the recorded t went to the lower prim
        CHECK(out[i].t == (closer ? t2[i] : t1[i]));
        CHECK(out[i].u == 0.125f);
        CHECK(out[i].v == 0.5f);
        CHECK(lane(p.tfar, i) == out[i].t);
    }
    CHECK_FALSE(out[n].is_hit());  // only lanes<T> records written
}

TEST_CASE_TEMPLATE("WideRay: broadcasts slab_ray's and woop_shear's constants bit for bit", T, float, ARBOR_TEST_BATCHES) {
    const std::vector<Ray> rays = arbor::testing::stiff_rays(13, 500, {{0, 0, 0}, {1, -1, 0.5f}});
    Mismatches bad;
    for (const Ray& ray : rays) {
        const WideRay<T> w = wide_ray<T>(ray.org, ray.dir, ray.tnear, ray.tfar);
        const SlabRay s = slab_ray(ray.org, ray.dir);
        const WoopShear sh = woop_shear(ray.dir);
        const bool ok = arbor::accel::ray_is_traceable(ray);
        if (w.traceable != ok) bad.add("traceable", &ray - rays.data());
        if (w.kx != sh.kx || w.ky != sh.ky || w.kz != sh.kz) bad.add("axes", &ray - rays.data());
        for (std::size_t i = 0; i < lanes<T>; ++i) {
            for (int k = 0; k < 3; ++k) {
                if (!same_float(lane(w.rcp_near[k], i), s.rcp_near[k])) bad.add("rcp_near", &ray - rays.data(), k);
                if (!same_float(lane(w.rcp_far[k], i), s.rcp_far[k])) bad.add("rcp_far", &ray - rays.data(), k);
                if (w.near_is_hi[k] != s.near_is_hi[k]) bad.add("near_is_hi", &ray - rays.data(), k);
                if (bits_of(lane(w.org[k], i)) != bits_of(ray.org[k])) bad.add("org", &ray - rays.data(), k);
            }
            const Vec3f op{ray.org[sh.kx], ray.org[sh.ky], ray.org[sh.kz]};
            for (int k = 0; k < 3; ++k)
                if (bits_of(lane(w.org_perm[k], i)) != bits_of(op[k])) bad.add("org_perm", &ray - rays.data(), k);
            if (!same_float(lane(w.sx, i), sh.sx) || !same_float(lane(w.sy, i), sh.sy) || !same_float(lane(w.sz, i), sh.sz))
                bad.add("shear", &ray - rays.data());
            const float tn = ok ? ray.tnear : INFINITY, tf = ok ? ray.tfar : -INFINITY;
            if (bits_of(lane(w.tnear, i)) != bits_of(tn) || bits_of(lane(w.tfar, i)) != bits_of(tf))
                bad.add("range", &ray - rays.data());
        }
    }
    ARBOR_CHECK_NONE(bad);
}
