// simd::bounds_boxes (the packet's interval bounds against a node's child boxes) is conservative
// lane by lane: whenever packet_box says some lane of the bounded set hits a box, the bounds keep
// that box. Inputs: stiff rays (axis-parallel with +-0, through box faces and corners, negative and
// varied tnear/tfar), coherent and incoherent packets, random lane subsets, flat/point/empty boxes.
// And the bounds do cull: a coherent packet drops boxes it cannot reach.
#include "simd/box_kernels.h"
#include "simd/packet_bounds.h"
#include "simd/tri_kernels.h"
#include "simd_cases.h"

#include <algorithm>
#include <array>

using namespace arbor::simd;
using arbor::testing::Mismatches;
using arbor::testing::Ray;

namespace {

struct Box {
    Vec3f lo, hi;
};

std::vector<Box> boxes(std::mt19937& rng) {
    std::vector<Box> b{{{-1, -1, -1}, {1, 1, 1}},     {{0, 0, 0}, {1, 1, 1}},       {{-1, 0.5f, 0}, {0, 1, 1}},
                       {{0, 0, 0}, {1, 1, 0}},         {{0.25f, -1, 1}, {0.25f, 1, 1}}, {{0, 0, 0}, {0, 0, 0}},
                       {{-2, -2, -2}, {-1, -1, -1}},   {{1e6f, 1e6f, 1e6f}, {1e6f + 1, 1e6f + 1, 1e6f + 1}}};
    for (int i = 0; i < 40; ++i) {
        const Vec3f a = arbor::testing::uniform3(rng, -2.5f, 2.5f), c = arbor::testing::uniform3(rng, -2.5f, 2.5f);
        b.push_back({vmin(a, c), vmax(a, c)});
    }
    return b;
}

/// Packets of lanes<P> rays taken from `rays` in several ways: consecutive, every k-th, and a
/// coherent bundle around each ray; each with a few lane subsets.
template <class P> void check_all(const std::vector<Ray>& rays, const std::vector<Box>& bx, Mismatches& miss, std::size_t& culled) {
    constexpr std::size_t K = lanes<P>;
    std::mt19937 rng(7);
    std::vector<std::vector<Ray>> packets;
    for (std::size_t i = 0; i + K <= rays.size(); i += K / 2) packets.emplace_back(rays.begin() + std::ptrdiff_t(i), rays.begin() + std::ptrdiff_t(i + K));
    for (std::size_t i = 0; i < rays.size(); i += 3) {
        std::vector<Ray> bundle;
        for (std::size_t l = 0; l < K; ++l) {
            Ray r = rays[i];
            if (l % 4 != 0) {  // jittered copies; every fourth lane keeps the exact stiff ray
                r.org = r.org + arbor::testing::uniform3(rng, -0.05f, 0.05f);
                r.dir = r.dir + arbor::testing::uniform3(rng, -0.05f, 0.05f);
                if (l % 3 == 0) r.tnear = -1.5f;  // negative tnear: rays that start behind their origin
            }
            bundle.push_back(r);
        }
        packets.push_back(bundle);
    }
    for (const auto& rs : packets) {
        const RayPacket<P> p = load_packet<P>(std::span<const Ray>(rs));
        for (const std::uint32_t subset : {0xFFFFFFFFu, 0x5555u, 0x0F0Fu, 0x1u, 0x8000u, std::uint32_t(rng())}) {
            const Mask<P> lanes = p.active & from_bits<P>(subset);
            const std::uint32_t lb = to_bits(lanes);
            const PacketBounds pb = packet_bounds(p, lanes);
            float tfar_hi = -INFINITY;
            for (std::size_t l = 0; l < K; ++l)
                if ((lb >> l) & 1u) tfar_hi = std::max(tfar_hi, lane(p.tbox, l));  // (packet_box's far distance)
            for (std::size_t first = 0; first < bx.size(); ++first) {
                alignas(64) BoxesSoA<1> soa;
                soa.set(0, bx[first].lo, bx[first].hi);
                const bool keep = bounds_boxes<float>(pb, tfar_hi, &soa.b[0][0][0]);
                P t;
                const std::uint32_t hit = to_bits(packet_box(p, bx[first].lo, bx[first].hi, t) & lanes);
                if (hit != 0 && !keep) miss.add("box", first, "lanes", hit, "subset", subset);
                culled += (lb != 0 && !keep);
            }
        }
    }
}

/// The same through the wide instantiation T: lanes<T> boxes per test, lane by lane against T = float.
template <class T, class P> void check_wide(const std::vector<Ray>& rays, const std::vector<Box>& bx, Mismatches& miss) {
    constexpr std::size_t n = lanes<T>;
    for (std::size_t i = 0; i + lanes<P> <= rays.size(); i += lanes<P>) {
        const RayPacket<P> p = load_packet<P>(std::span<const Ray>(rays.data() + i, lanes<P>));
        const PacketBounds pb = packet_bounds(p, p.active);
        const float tfar_hi = 3.0f;
        for (std::size_t first = 0; first + n <= bx.size(); first += n) {
            BoxesSoA<n> soa;
            for (std::size_t c = 0; c < n; ++c) soa.set(c, bx[first + c].lo, bx[first + c].hi);
            if (first == 0) soa.set_empty(n - 1);
            const std::uint32_t wide = to_bits(bounds_boxes<T>(pb, tfar_hi, &soa.b[0][0][0]));
            for (std::size_t c = 0; c < n; ++c) {
                BoxesSoA<1> one;
                for (int k = 0; k < 3; ++k) one.b[0][k][0] = soa.b[0][k][c], one.b[1][k][0] = soa.b[1][k][c];
                const bool scalar = bounds_boxes<float>(pb, tfar_hi, &one.b[0][0][0]);
                if (scalar != bool((wide >> c) & 1u)) miss.add("lane", c, "box", first + c);
            }
        }
    }
}

}  // namespace

TEST_CASE_TEMPLATE("packet bounds: never drop a box that a lane of the packet hits", P, ARBOR_TEST_BATCHES) {
    std::mt19937 rng(3);
    const std::vector<Box> bx = boxes(rng);
    std::vector<Vec3f> targets{{1, 1, 1}, {-1, -1, -1}, {0, 0, 0}, {0.25f, 0.5f, 1}, {1, 0, -1}, {-1, 0.5f, 0}, {0.5f, 0.5f, 0}};
    std::vector<Ray> rays = arbor::testing::stiff_rays(11, 200, targets);
    // Near-axis directions whose small components slab_rcp turns into NaN or +-inf reciprocals.
    for (const float tiny : {1e-39f, -1e-39f, 1e-30f, 3e-38f, -0.0f})
        for (const Vec3f& o : {Vec3f{-3, 0.5f, 0.25f}, Vec3f{-3, 1, 1}, Vec3f{-3, -1, 0}})
            rays.push_back({o, 0.0f, {1.0f, tiny, -tiny * 0.5f}, INFINITY});
    Mismatches miss;
    std::size_t culled = 0;
    check_all<P>(rays, bx, miss, culled);
    ARBOR_CHECK_NONE(miss);
    CHECK(culled > 0);
}

/// The packets of the cases below: 8 lanes, or 4 in a build without AVX2 (the portable build's tests
/// are compiled for x86-64-v2; its kernel sets run the 8- and 16-lane packets, test_kernel_set.cpp).
#if XSIMD_WITH_AVX2
using Packet8 = Float8;
#else
using Packet8 = Float4;
#endif
constexpr std::size_t packet8 = lanes<Packet8>;

TEST_CASE_TEMPLATE("packet bounds: wide instantiations agree with T = float lane by lane", T, ARBOR_TEST_BATCHES) {
    std::mt19937 rng(5);
    const std::vector<Box> bx = boxes(rng);
    const std::vector<Ray> rays = arbor::testing::stiff_rays(13, 120, {{1, 1, 1}, {0, 0, 0}, {-1, 0.5f, 0}});
    Mismatches miss;
    check_wide<T, Packet8>(rays, bx, miss);
    ARBOR_CHECK_NONE(miss);
}

TEST_CASE("packet bounds: a coherent packet keeps the box it looks at and drops the others") {
    std::vector<Ray> rays;
    for (int i = 0; i < 8; ++i) rays.push_back({{0.01f * float(i), 0.0f, -5.0f}, 0.0f, {0.001f * float(i), 0.002f, 1.0f}, INFINITY});
    const RayPacket<Packet8> p = load_packet<Packet8>(std::span<const Ray>(rays));
    const PacketBounds pb = packet_bounds(p, p.active);
    CHECK(pb.axes == 7u);
    BoxesSoA<4> soa;
    soa.set(0, {-1, -1, -1}, {1, 1, 1});  // in front
    soa.set(1, {3, -1, -1}, {4, 1, 1});   // beside
    soa.set(2, {-1, -1, -9}, {1, 1, -6}); // behind
    soa.set_empty(3);
    CHECK(to_bits(bounds_boxes<Float4>(pb, INFINITY, &soa.b[0][0][0])) == 1u);
    CHECK(to_bits(bounds_boxes<Float4>(pb, 3.0f, &soa.b[0][0][0])) == 0u);  // tfar before the box
}

TEST_CASE_TEMPLATE("packet bounds: never drop a triangle that a lane of the packet hits", T, ARBOR_TEST_BATCHES) {
    constexpr std::size_t n = lanes<T>;
    std::mt19937 rng(9);
    // Triangles around [-1, 1]^3, with vertices and edges on the stiff rays' targets.
    std::vector<std::array<Vec3f, 3>> tris{{{{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}}}, {{{-1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}},
                                           {{{0, 0, 0}, {1, 0, 1}, {0, 1, 1}}},    {{{1, 1, 1}, {-1, 0.5f, 0}, {0.25f, 0.5f, 1}}}};
    for (int i = 0; i < 60; ++i)
        tris.push_back({arbor::testing::uniform3(rng, -1.5f, 1.5f), arbor::testing::uniform3(rng, -1.5f, 1.5f),
                        arbor::testing::uniform3(rng, -1.5f, 1.5f)});
    const std::vector<Ray> rays = arbor::testing::stiff_rays(17, 300, {{1, 1, 1}, {0, 0, 0}, {-1, 0.5f, 0}, {1, -1, 0}, {0.5f, 0.5f, 1}});
    Mismatches miss;
    std::size_t culled = 0;
    for (std::size_t i = 0; i + packet8 <= rays.size(); i += 4) {
        const RayPacket<Packet8> p = load_packet<Packet8>(std::span<const Ray>(rays.data() + i, packet8));
        const PacketBounds pb = packet_bounds(p, p.active);
        float tfar_hi = -INFINITY;
        for (std::size_t l = 0; l < packet8; ++l)
            if (lane(p.active, l)) tfar_hi = std::max(tfar_hi, lane(p.tbox, l));  // (as the packet walks' leaves)
        for (std::size_t first = 0; first < tris.size(); first += n) {
            TrisSoA<n> block;
            for (std::size_t c = 0; c < n; ++c) {
                if (first + c < tris.size()) block.set(c, tris[first + c][0], tris[first + c][1], tris[first + c][2]);
                else block.set_empty(c);
            }
            const std::uint32_t keep = to_bits(bounds_triangles<T>(pb, tfar_hi, &block.v[0][0][0]));
            for (std::size_t c = 0; c < n && first + c < tris.size(); ++c) {
                const auto& t = tris[first + c];
                const std::uint32_t hit = to_bits(packet_triangle(p, t[0], t[1], t[2]).hit);
                if (hit != 0 && !((keep >> c) & 1u)) miss.add("triangle", first + c, "lanes", hit, "packet", i);
                culled += to_bits(p.active) != 0 && !((keep >> c) & 1u);
            }
        }
    }
    ARBOR_CHECK_NONE(miss);
    CHECK(culled > 0);
}

#if XSIMD_WITH_AVX512F
TEST_CASE("packet bounds: hmin16 is sixteen reductions") {
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> u(-1e3f, 1e3f);
    Mismatches miss;
    for (int round = 0; round < 200; ++round) {
        alignas(64) float x[16][16];
        Float16 v[16];
        for (int i = 0; i < 16; ++i) {
            for (int l = 0; l < 16; ++l) x[i][l] = round % 7 == 0 && l != i ? INFINITY : u(rng);
            v[i] = Float16::load_aligned(x[i]);
        }
        float got[16];
        hmin16(v, got);
        for (int i = 0; i < 16; ++i)
            if (got[i] != hmin(v[i])) miss.add("round", round, "vector", i);
    }
    ARBOR_CHECK_NONE(miss);
}

TEST_CASE("packet bounds: the batched 16-lane bounds equal the plain ones") {
    std::vector<Ray> rays = arbor::testing::stiff_rays(23, 300, {{1, 1, 1}, {0, 0, 0}, {-1, 0.5f, 0}, {0.25f, 0.5f, 1}});
    for (const float tiny : {1e-39f, -1e-39f, 1e-30f, 3e-38f, -0.0f})
        for (const Vec3f& o : {Vec3f{-3, 0.5f, 0.25f}, Vec3f{-3, 1, 1}, Vec3f{-3, -1, 0}})
            rays.push_back({o, 0.0f, {1.0f, tiny, -tiny * 0.5f}, INFINITY});
    std::mt19937 rng(25);
    std::shuffle(rays.begin() + 100, rays.end(), rng);  // mixed and shared signs, partial packets
    Mismatches miss;
    std::size_t axes = 0, batched = 0;
    for (std::size_t i = 0; i < rays.size(); i += 5) {
        const std::size_t n = std::min<std::size_t>(16, rays.size() - i);
        const RayPacket<Float16> p = load_packet<Float16>(std::span<const Ray>(rays.data() + i, n));
        for (const std::uint32_t subset : {0xFFFFu, 0x0F0Fu, 0x1u, 0x8001u, std::uint32_t(rng())}) {
            const Mask<Float16> lanes = p.active & from_bits<Float16>(subset);
            const PacketBounds a = packet_bounds(p, lanes), b = packet_bounds_plain(p, lanes);
            bool same = a.axes == b.axes && a.tnear_lo == b.tnear_lo;
            for (int k = 0; k < 3; ++k)
                if ((b.axes >> k) & 1u)
                    same = same && a.neg[k] == b.neg[k] && a.o_lo[k] == b.o_lo[k] && a.o_hi[k] == b.o_hi[k] &&
                           a.rn_lo[k] == b.rn_lo[k] && a.rn_hi[k] == b.rn_hi[k] && a.rf_lo[k] == b.rf_lo[k] &&
                           a.rf_hi[k] == b.rf_hi[k];
            if (!same) miss.add("first ray", i, "subset", subset);
            axes += std::popcount(b.axes);
            batched += std::popcount(b.axes) >= 2;  // two axes or more: the batched form ran
        }
    }
    ARBOR_CHECK_NONE(miss);
    CHECK(axes > 100);  // the comparison saw axes that take part, not only left-out ones
    CHECK(batched > 20);
}
#endif
