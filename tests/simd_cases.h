#pragma once
/// Inputs that stress the SIMD kernels (rays, boxes, triangles) and a mismatch counter, shared by
/// the lane-by-lane tests of test_simd.cpp and test_simd_kernels.cpp.
#include "accel/core/ray.h"
#include "simd/simd.h"

#include <doctest/doctest.h>

#include <bit>
#include <cstdint>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace arbor::testing {

using accel::Ray;
using simd::Vec3f;

/// The batch types every kernel is instantiated for in this build.
#if XSIMD_WITH_AVX512F
#define ARBOR_TEST_BATCHES arbor::simd::Float4, arbor::simd::Float8, arbor::simd::Float16
#elif XSIMD_WITH_AVX2
#define ARBOR_TEST_BATCHES arbor::simd::Float4, arbor::simd::Float8
#else
#define ARBOR_TEST_BATCHES arbor::simd::Float4
#endif

inline std::uint32_t bits_of(float x) { return std::bit_cast<std::uint32_t>(x); }

/// Counts disagreements and keeps the first one's description, so that a loop over thousands of
/// lanes costs one doctest assertion and still says what went wrong.
struct Mismatches {
    std::size_t count = 0;
    std::string first;
    template <class... Args> void add(const Args&... what) {
        if (count++ == 0) {
            std::ostringstream s;
            s.precision(9);
            ((s << what << ' '), ...);
            first = s.str();
        }
    }
};
#define ARBOR_CHECK_NONE(m)                                                                                         \
    do {                                                                                                            \
        INFO("first mismatch: " << (m).first);                                                                      \
        CHECK((m).count == 0);                                                                                      \
    } while (0)

inline float uniform(std::mt19937& rng, float lo, float hi) {
    return std::uniform_real_distribution<float>(lo, hi)(rng);
}
inline Vec3f uniform3(std::mt19937& rng, float lo, float hi) {
    return {uniform(rng, lo, hi), uniform(rng, lo, hi), uniform(rng, lo, hi)};
}

/// Axis-parallel rays through p along +-x, +-y, +-z, with every combination of +0/-0 in the other
/// two components, starting 2 units away (exactly, for p in [-1, 1]).
inline void add_axis_rays(std::vector<Ray>& rays, const Vec3f& p) {
    for (int axis = 0; axis < 3; ++axis)
        for (float s : {1.0f, -1.0f})
            for (int zeros = 0; zeros < 4; ++zeros) {
                Vec3f d{0.0f, 0.0f, 0.0f};
                d[(axis + 1) % 3] = (zeros & 1) ? -0.0f : 0.0f;
                d[(axis + 2) % 3] = (zeros & 2) ? -0.0f : 0.0f;
                d[axis] = s;
                Vec3f o = p;
                o[axis] -= 2.0f * s;
                rays.push_back({o, 0.0f, d, INFINITY});
            }
}

/// Rays that no kernel may accept: NaN/Inf components, zero direction, inactive (tfar < tnear),
/// NaN range ends. Each one passes through the origin region so it would hit if it were traced.
inline void add_untraceable_rays(std::vector<Ray>& rays) {
    const float nan = NAN, inf = INFINITY;
    const Vec3f o{0.1f, 0.2f, 3.0f}, d{0.01f, -0.02f, -1.0f};
    rays.push_back({{nan, o.y, o.z}, 0.0f, d, inf});
    rays.push_back({o, 0.0f, {d.x, nan, d.z}, inf});
    rays.push_back({{o.x, o.y, inf}, 0.0f, d, inf});
    rays.push_back({o, 0.0f, {d.x, d.y, -inf}, inf});
    rays.push_back({o, 0.0f, {0.0f, -0.0f, 0.0f}, inf});
    rays.push_back({o, 5.0f, d, 1.0f});    // tfar < tnear
    rays.push_back({o, nan, d, inf});
    rays.push_back({o, 0.0f, d, nan});
}

/// Random rays from around [-1, 1]^3 towards points inside it, plus oblique rays through each
/// target point (vertices, edge points, box corners) and axis-parallel ones through them, plus
/// the untraceable rays; tnear/tfar vary so that range checks are exercised.
inline std::vector<Ray> stiff_rays(std::uint32_t seed, std::size_t n_random, const std::vector<Vec3f>& targets) {
    std::mt19937 rng(seed);
    std::vector<Ray> rays;
    for (std::size_t i = 0; i < n_random; ++i) {
        const Vec3f o = uniform3(rng, -3.0f, 3.0f), to = uniform3(rng, -1.0f, 1.0f);
        const float tnear = (i % 7 == 0) ? uniform(rng, 0.0f, 0.5f) : 0.0f;
        const float tfar = (i % 5 == 0) ? uniform(rng, 0.5f, 1.5f) : INFINITY;
        rays.push_back({o, tnear, to - o, tfar});
    }
    for (const Vec3f& p : targets) {
        const Vec3f d = uniform3(rng, -1.0f, 1.0f);
        rays.push_back({p - d * 3.0f, 0.0f, d, INFINITY});
        add_axis_rays(rays, p);
    }
    add_untraceable_rays(rays);
    return rays;
}

}  // namespace arbor::testing
