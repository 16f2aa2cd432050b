// The single-ray walk's child order (wide_order.h) and push (wide_push.h): every node's order per
// octant is a permutation with the unused slots first and the children far to near along the
// octant's diagonal; the AVX-512 push writes what the plain loop writes, entry for entry; and the
// walk that uses both finds the same closest hits as the scalar path (test_wide_paths.cpp checks
// every path against brute on every model).
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>
#include <random>

#include "accel/bvh/bvh_build.h"
#include "accel/wide/wide_order.h"
#include "accel/wide/wide_packet.h"
#include "accel/wide/wide_push.h"
#include "engine/procedural.h"
#include "testing.h"

using namespace arbor;
using accel::Vec3f;

namespace {

template <std::size_t N>
float order_key(const accel::WideNode<N>& n, std::size_t c, int octant) {
    float key = 0.0f;
    for (int k = 0; k < 3; ++k) {
        const float centre2 = n.boxes.b[0][k][c] + n.boxes.b[1][k][c];
        key += (octant >> k) & 1 ? -centre2 : centre2;
    }
    return key;
}

template <std::size_t N>
void check_orders(const accel::WideLayout<N>& L) {
    REQUIRE(L.orders.size() == L.nodes.size() * 8 * N);
    std::size_t bad_perm = 0, bad_unused = 0, bad_key = 0, bad_tie = 0;
    for (std::size_t i = 0; i < L.nodes.size(); ++i) {
        const auto& n = L.nodes[i];
        for (int o = 0; o < 8; ++o) {
            const std::uint8_t* row = &L.orders[(i * 8 + std::size_t(o)) * N];
            std::vector<int> seen(N, 0);
            for (std::size_t j = 0; j < N; ++j) bad_perm += row[j] >= N || seen[row[j]]++ != 0;
            const std::size_t unused = N - n.children;
            for (std::size_t j = 0; j < N; ++j) bad_unused += (j < unused) != (row[j] >= n.children);
            for (std::size_t j = unused + 1; j < N; ++j) {
                const float far = order_key(n, row[j - 1], o), near = order_key(n, row[j], o);
                bad_key += far < near;
                bad_tie += far == near && row[j - 1] < row[j];  // equal keys: the lower lane nearer
            }
        }
    }
    CHECK(bad_perm == 0);
    CHECK(bad_unused == 0);
    CHECK(bad_key == 0);
    CHECK(bad_tie == 0);
}

template <std::size_t N>
accel::WideLayout<N> layout_of(const engine::Mesh& mesh) {
    const accel::PrimRefs refs = accel::make_prim_refs(mesh.view());
    return accel::make_wide_layout<N>(accel::build_bvh_sah(refs, {}), mesh.view());
}

/// A node of `children` random children (random references, counts and distances).
template <std::size_t N>
accel::WideNode<N> random_node(std::mt19937& rng, std::size_t children) {
    accel::WideNode<N> n{};
    for (std::size_t c = 0; c < N; ++c) {
        n.child[c] = rng();
        n.count[c] = std::uint16_t(rng() % 3 == 0 ? 0 : rng() % 65536);
    }
    n.children = std::uint8_t(children);
    return n;
}

/// The N-wide bvh-sah layout of `m` with one triangle per leaf and no leaves merged.
template <std::size_t N>
accel::WideLayout<N> one_leaf_each(const engine::Mesh& m) {
    accel::BvhBuildConfig bc;
    bc.max_leaf_size = 1;
    accel::WideConfig wc;
    wc.merge_triangles = 1;
    const accel::PrimRefs refs = accel::make_prim_refs(m.view());
    return accel::make_wide_layout<N>(accel::build_bvh_sah(refs, bc), m.view(), wc);
}

}  // namespace

TEST_CASE("wide order: a permutation per node and octant, unused slots first, children far to near") {
    const engine::Mesh mesh = testing::procedural_shapes();
    check_orders<4>(layout_of<4>(mesh));
    check_orders<8>(layout_of<8>(mesh));
    check_orders<16>(layout_of<16>(mesh));
}

TEST_CASE("wide order: children along the x axis come far to near for rays going +x and -x") {
    // Sixteen unit cubes in a row along x, one triangle each: the root holds them all.
    engine::Mesh row;
    for (std::uint32_t i = 0; i < 16; ++i) {
        const float x = float(i) * 3.0f;
        row.add_vertex({x, 0, 0}), row.add_vertex({x + 1, 1, 0}), row.add_vertex({x, 1, 1});
        row.add_triangle(3 * i, 3 * i + 1, 3 * i + 2);
    }
    row.compute_bounds();
    const auto L = one_leaf_each<16>(row);
    REQUIRE(L.nodes.size() == 1);
    REQUIRE(L.nodes[0].children == 16);
    check_orders<16>(L);
    for (const int octant : {0, 1}) {  // +x (and +y +z), then -x
        const std::uint8_t* o = &L.orders[std::size_t(octant) * 16];
        for (int j = 1; j < 16; ++j) {
            const float far = L.nodes[0].boxes.b[0][0][o[j - 1]], near = L.nodes[0].boxes.b[0][0][o[j]];
            CAPTURE(octant);
            CHECK((octant == 0 ? far > near : far < near));
        }
    }
}

TEST_CASE("wide order: the same orders with 1 and 2 threads") {
    const engine::Mesh mesh = testing::procedural_shapes();
    const auto a = layout_of<16>(mesh);
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    const auto b = layout_of<16>(mesh);
    CHECK(std::equal(a.orders.begin(), a.orders.end(), b.orders.begin(), b.orders.end()));
}

TEST_CASE_TEMPLATE("wide push: every hit child once, in the given order, the top moved by the hits", W,
                   std::integral_constant<std::size_t, 4>, std::integral_constant<std::size_t, 8>,
                   std::integral_constant<std::size_t, 16>) {
    constexpr std::size_t N = W::value;
    std::mt19937 rng(7);
    accel::WideStack s(64);
    std::size_t bad = 0;
    for (int round = 0; round < 2000; ++round) {
        const auto n = random_node<N>(rng, 1 + rng() % N);
        std::uint8_t order[N];
        std::iota(order, order + N, 0);
        std::shuffle(order, order + N, rng);
        float d[N];
        for (auto& x : d) x = float(rng() % 1000) * 0.5f;
        const std::uint32_t bits = std::uint32_t(rng()) & ((1u << N) - 1u);
        const std::size_t sp0 = rng() % 32;
        const std::size_t sp = accel::push_ordered<N>(bits, order, n, d, s, sp0);
        std::size_t k = sp0;
        bad += sp != sp0 + std::size_t(std::popcount(bits));
        for (std::size_t j = 0; j < N && k < sp; ++j) {
            const unsigned l = order[j];
            if (!((bits >> l) & 1u)) continue;
            bad += s.child()[k] != n.child[l] || s.count()[k] != n.count[l] || s.t()[k] != d[l];
            ++k;
        }
    }
    CHECK(bad == 0);
}

TEST_CASE_TEMPLATE("wide packet order: ordered_bits ranks the hit children by the node's order", W,
                   std::integral_constant<std::size_t, 4>, std::integral_constant<std::size_t, 8>,
                   std::integral_constant<std::size_t, 16>) {
    // The packet walk pushes a node's hit children in the order of the bits ordered_bits returns
    // (far to near) and visits the highest next: bit j must be set exactly when child order[j] hit.
    constexpr std::size_t N = W::value;
    constexpr std::uint32_t all = (1u << N) - 1u;
    std::mt19937 rng(17);
    std::size_t bad = 0, set = 0;
    for (int round = 0; round < 5000; ++round) {
        std::uint8_t order[N];
        std::iota(order, order + N, 0);
        std::shuffle(order, order + N, rng);
        const std::uint32_t hits = round == 0 ? 0u : round == 1 ? all : round == 2 ? 1u << (N - 1) : rng() & all;
        const std::uint32_t ranked = accel::ordered_bits<N>(hits, order);
        bad += (ranked & ~all) != 0 || std::popcount(ranked) != std::popcount(hits);
        for (std::size_t j = 0; j < N; ++j) bad += ((ranked >> j) & 1u) != ((hits >> order[j]) & 1u);
        set += std::size_t(std::popcount(ranked));
    }
    CHECK(bad == 0);
    CHECK(set > 5000 * N * 3 / 8);
}

namespace {

/// A vector push (`push(bits, order, node, d, stack, sp)`, d 64-byte aligned) against the plain loop
/// on random nodes, orders, distances, masks (and the edge cases none, the top lane alone, all) and
/// stack positions: the same top and the same entries.
template <std::size_t N, class Push>
void check_vector_push(std::uint32_t seed, Push&& push) {
    std::mt19937 rng(seed);
    accel::WideStack a(64), b(64);
    constexpr std::uint32_t all = (1u << N) - 1u;
    std::size_t bad = 0, pushed = 0;
    for (int round = 0; round < 5000; ++round) {
        const auto n = random_node<N>(rng, 1 + rng() % N);
        std::uint8_t order[N];
        std::iota(order, order + N, 0);
        std::shuffle(order, order + N, rng);
        alignas(64) float d[N];
        for (auto& x : d) x = std::ldexp(float(rng() % 100000), int(rng() % 40) - 20);
        const std::uint32_t bits = round == 0 ? 0u : round == 1 ? 1u << (N - 1) : round == 2 ? all : rng() & all;
        const std::size_t sp0 = rng() % 40;
        const std::size_t sa = accel::push_ordered<N>(bits, order, n, d, a, sp0);
        const std::size_t sb = push(bits, order, n, static_cast<const float*>(d), b, sp0);
        bad += sa != sb;
        for (std::size_t k = sp0; k < std::min(sa, sb); ++k)
            bad += a.child()[k] != b.child()[k] || a.count()[k] != b.count()[k] || a.t()[k] != b.t()[k];
        pushed += sa - sp0;
    }
    CHECK(bad == 0);
    CHECK(pushed > 5000 * N * 3 / 8);  // about half the lanes of each node hit
}

}  // namespace

#if XSIMD_WITH_AVX2
TEST_CASE("wide push: the AVX2 push writes what the plain loop writes") {
    check_vector_push<8>(13, [](std::uint32_t bits, const std::uint8_t* order, const accel::WideNode<8>& n,
                                const float* d, accel::WideStack& s, std::size_t sp) {
        return accel::push_ordered8(bits, order, n, _mm256_load_ps(d), s, sp);
    });
}
#endif

#if XSIMD_WITH_AVX512F
TEST_CASE("wide push: the AVX-512 push writes what the plain loop writes") {
    check_vector_push<16>(11, [](std::uint32_t bits, const std::uint8_t* order, const accel::WideNode<16>& n,
                                 const float* d, accel::WideStack& s, std::size_t sp) {
        return accel::push_ordered16(bits, order, n, _mm512_load_ps(d), s, sp);
    });
}
#endif

TEST_CASE("wide order: children with equal keys keep the lower lane nearer in every octant") {
    // Sixteen small triangles on a 4 x 4 grid in the z = 0 plane: along the diagonals that the
    // octants' keys measure, many children tie (each octant's order is made from its opposite's).
    engine::Mesh grid;
    for (std::uint32_t i = 0; i < 16; ++i) {
        const float x = float(i % 4) * 3.0f, y = float(i / 4) * 3.0f;
        grid.add_vertex({x, y, 0}), grid.add_vertex({x + 1, y, 0}), grid.add_vertex({x, y + 1, 0});
        grid.add_triangle(3 * i, 3 * i + 1, 3 * i + 2);
    }
    grid.compute_bounds();
    const auto L = one_leaf_each<16>(grid);
    REQUIRE(L.nodes.size() == 1);
    REQUIRE(L.nodes[0].children == 16);
    check_orders<16>(L);
}
