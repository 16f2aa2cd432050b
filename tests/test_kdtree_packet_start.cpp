// The kd-tree packet walk's start (kdtree_stack_packet.h, PacketStack::start): all lanes of an
// octant group set up at once in double SIMD must be in exactly the state the scalar start gives
// them (stack_start, then set_lane; clear_lane for lanes it does not start), bit for bit: the
// packet walk's exactness argument (each lane takes its scalar walk's decisions) starts there.
// Rays: random ones in and around the scene box, and the stiff ones: zero direction components
// (+0 and -0) with origins on, just inside and just outside the box's planes, origins on the box's
// faces and corners (crossings of -0 and +0, tied with tnear +-0), tnear beyond the box, negative tnear, short tfar.
#include "accel/kdtree/kdtree_build.h"
#include "accel/kdtree/kdtree_stack_packet.h"
#include "engine/procedural.h"
#include "kdtree_checks.h"
#include "testing.h"

#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

using namespace arbor;
using accel::Ray;
using accel::Vec3f;
namespace kd = accel::kd;

namespace {

/// Rays whose directions have the signs of octant `oct` (bit k set: d_k has its sign bit set).
std::vector<Ray> octant_rays(const accel::KdTree& tree, unsigned oct, std::uint32_t seed, std::size_t count) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const Vec3f lo = tree.box.lo, hi = tree.box.hi;
    std::vector<Ray> rays;
    while (rays.size() < count) {
        Ray r;
        const int style = int(rng() % 7);
        for (int k = 0; k < 3; ++k) {
            const float ext = hi[k] - lo[k];
            float o = lo[k] - 0.5f * ext + 2.0f * ext * u(rng);  // in and around the box
            if (style == 6) o = (rng() & 1u) ? lo[k] : hi[k];  // a corner of the box: crossings of +-0 tie
            if (style == 1 || (style == 2 && k == int(rng() % 3))) {
                // On a plane of the box, or one float beside it.
                const float plane = (rng() & 1u) ? lo[k] : hi[k];
                const int step = int(rng() % 3) - 1;
                o = step == 0 ? plane : std::nextafter(plane, step < 0 ? -INFINITY : INFINITY);
            }
            float d = 0.05f + u(rng);
            if (style >= 2 && rng() % 3 == 0) d = 0.0f;  // flat axis
            if (style == 5) d = std::ldexp(d, -int(rng() % 30));  // tiny components
            r.org[k] = o;
            r.dir[k] = (oct >> k & 1u) ? -d : d;  // -0.0f for a flat axis with the sign bit
        }
        if (r.dir.x == 0.0f && r.dir.y == 0.0f && r.dir.z == 0.0f) continue;
        switch (style == 6 ? 4 * (rng() % 2) : rng() % 5) {
        case 0: r.tnear = 0.0f, r.tfar = INFINITY; break;
        case 1: r.tnear = -2.0f * u(rng), r.tfar = INFINITY; break;  // negative tnear
        case 2: r.tnear = 0.0f, r.tfar = 3.0f * u(rng); break;         // may end before the box
        case 3: r.tnear = 5.0f * u(rng), r.tfar = r.tnear + 0.1f; break;  // may start beyond it
        default: r.tnear = (rng() & 1u) ? -0.0f : 0.0f, r.tfar = 1e30f; break;
        }
        rays.push_back(r);
    }
    return rays;
}

template <class T> bool same_bits(const T& a, const T& b) { return std::memcmp(&a, &b, sizeof(T)) == 0; }

/// Every packet of K rays of each octant through PacketStack::start against the scalar start, with
/// random groups of lanes; counts the lanes started (so that the cases are not all misses).
template <class P> void check_start(const accel::KdTree& tree, std::uint32_t seed, std::size_t& started,
                                    std::size_t& checked) {
    constexpr std::size_t K = simd::lanes<P>;
    std::mt19937 rng(seed);
    for (unsigned oct = 0; oct < 8; ++oct) {
        const std::vector<Ray> rays = octant_rays(tree, oct, seed + oct, 64 * K);
        for (std::size_t base = 0; base < rays.size(); base += K) {
            std::uint32_t group = (K == 32 ? ~0u : (1u << K) - 1u);
            if (rng() % 2) group &= std::uint32_t(rng());
            kd::PacketStack<K> want, got;
            alignas(64) float org[3][K], dir[3][K], tnear[K], tfar[K];
            std::uint32_t live = 0;
            for (int k = 0; k < 3; ++k) want.neg[k] = got.neg[k] = (oct >> k) & 1u;
            for (std::size_t i = 0; i < K; ++i) {
                const Ray& r = rays[base + i];
                for (int k = 0; k < 3; ++k) org[k][i] = r.org[k], dir[k][i] = r.dir[k];
                tnear[i] = r.tnear, tfar[i] = r.tfar;
                kd::StackWalk w;
                if ((group >> i & 1u) && accel::ray_is_traceable(r) && kd::stack_start(tree, r, w)) {
                    want.set_lane(i, w);
                    live |= 1u << i;
                } else {
                    want.clear_lane(i);
                }
            }
            // The caller passes only traceable lanes (the packet's active mask).
            std::uint32_t traceable = 0;
            for (std::size_t i = 0; i < K; ++i) traceable |= accel::ray_is_traceable(rays[base + i]) ? 1u << i : 0u;
            const std::uint32_t got_live = got.template start<P>(tree, org, dir, tnear, tfar, group & traceable);
            REQUIRE(got_live == live);
            started += std::size_t(std::popcount(live));
            for (int k = 0; k < 3; ++k) {
                CHECK(got.flat_bits[k] == want.flat_bits[k]);
                for (std::size_t i = 0; i < K; ++i) {
                    INFO("octant " << oct << " lane " << i << " axis " << k << " live " << (live >> i & 1u));
                    CHECK(same_bits(got.o[k][i], want.o[k][i]));
                    CHECK(same_bits(got.d[k][i], want.d[k][i]));
                    CHECK(same_bits(got.rcp[k][i], want.rcp[k][i]));
                    CHECK(same_bits(got.e[k][i], want.e[k][i]));
                    CHECK(same_bits(got.lo[k][i], want.lo[k][i]));
                    CHECK(same_bits(got.hi[k][i], want.hi[k][i]));
                }
            }
            for (std::size_t i = 0; i < K; ++i) {
                INFO("octant " << oct << " lane " << i << " live " << (live >> i & 1u));
                CHECK(same_bits(got.tmin[i], want.tmin[i]));
                CHECK(same_bits(got.tmax[i], want.tmax[i]));
            }
            checked += K;
        }
    }
}

template <class P> void check_all(const char* name) {
    INFO("lanes " << name);
    std::size_t started = 0, checked = 0;
    for (const float offset : {0.0f, 1e6f}) {
        engine::Mesh mesh = engine::make_icosphere({0, 0, 0}, 1.0f, 3, 0.15f, 5);
        mesh.append(testing::random_soup(300, 0.15f, 7));
        for (std::size_t i = 0; i < mesh.vertex_count(); ++i) mesh.x[i] += offset, mesh.y[i] -= offset;
        mesh.compute_bounds();
        check_start<P>(accel::build_kdtree(mesh.view()), 11, started, checked);
    }
    check_start<P>(accel::build_kdtree(testing::integer_cubes(3).view()), 23, started, checked);
    // Enough lanes started and enough not (missing the box, flat outside, tnear beyond it).
    CHECK(started > checked / 8);
    CHECK(started < checked * 7 / 8);
}

}  // namespace

TEST_CASE("kdtree packet start: every lane in exactly stack_start's state, bit for bit") {
    check_all<simd::Float4>("4");
#if XSIMD_WITH_AVX2
    check_all<simd::Float8>("8");
#endif
#if XSIMD_WITH_AVX512F
    check_all<simd::Float16>("16");
#endif
}
