// WideRaySetup (simd/wide_ray_setup.h): the set-up of a group of rays, worked out across lanes,
// gives each ray bit for bit the WideRay that wide_ray() gives it alone: every field, for every
// group width of the build, on stiff rays (axis-parallel with +-0, near-axis components whose
// reciprocal the slab rule turns into NaN or +-inf, ties between the largest components, huge and
// tiny directions, negative tnear, untraceable rays) and in partial groups.
#include "simd/wide_ray_setup.h"
#include "simd_cases.h"

#include <doctest/doctest.h>

#include <cstring>

using namespace arbor::simd;
using arbor::accel::Ray;
using arbor::accel::Vec3f;

namespace {

std::vector<Ray> setup_rays() {
    std::vector<Vec3f> targets{{0, 0, 0}, {1, 1, 1}, {0.5f, -0.5f, 0}, {-1, 0.25f, 0.75f}};
    std::vector<Ray> rays = arbor::testing::stiff_rays(5, 300, targets);
    const Vec3f o{0.3f, -0.2f, 0.1f};
    for (float s : {1.0f, -1.0f}) {
        // Ties between the largest |d| components (the Woop axis choice), with either sign.
        rays.push_back({o, 0.0f, {s, s, 0.5f}, INFINITY});
        rays.push_back({o, 0.0f, {s, -s, s}, INFINITY});
        rays.push_back({o, 0.0f, {0.25f, s, -s}, INFINITY});
        // Near-axis: a component far below FLT_MIN * dmax (reciprocal NaN), one whose ratio underflows.
        rays.push_back({o, 0.0f, {1e-30f * s, 0.5f, 1.0f}, INFINITY});
        rays.push_back({o, 0.0f, {1e-45f * s, -1.0f, 1e30f}, INFINITY});
        rays.push_back({o, 0.0f, {s * 3e38f, 1.0f, -2.0f}, INFINITY});
        rays.push_back({o, 0.0f, {s * 1e-38f, 2e-38f, -3e-38f}, INFINITY});
        // Negative and zero tnear, finite tfar.
        rays.push_back({o, -1.0f, {s, 0.2f, 0.3f}, 4.0f});
        rays.push_back({o, -0.0f, {0.2f, s, 0.3f}, 4.0f});
    }
    return rays;
}

template <class T> bool same_bits(const T& a, const T& b) { return std::memcmp(&a, &b, sizeof(T)) == 0; }

/// Field by field; untraceable rays only need traceable == false (their walk never starts).
template <class T> bool same_ray(const WideRay<T>& a, const WideRay<T>& b) {
    if (a.traceable != b.traceable) return false;
    if (!a.traceable) return true;
    for (int k = 0; k < 3; ++k)
        if (!same_bits(a.org[k], b.org[k]) || !same_bits(a.org_perm[k], b.org_perm[k]) ||
            !same_bits(a.rcp_near[k], b.rcp_near[k]) || !same_bits(a.rcp_far[k], b.rcp_far[k]) ||
            a.near_is_hi[k] != b.near_is_hi[k])
            return false;
    return same_bits(a.tnear, b.tnear) && same_bits(a.tfar, b.tfar) && same_bits(a.tbox, b.tbox) &&
           same_bits(a.sx, b.sx) && same_bits(a.sy, b.sy) && same_bits(a.sz, b.sz) && a.kx == b.kx && a.ky == b.ky &&
           a.kz == b.kz && a.plain == b.plain;
}

}  // namespace

TEST_CASE_TEMPLATE("wide_ray_setup: every ray of a group gets wide_ray()'s WideRay, bit for bit", P, ARBOR_TEST_BATCHES) {
    const std::vector<Ray> rays = setup_rays();
    WideRaySetup<P> setup;
    std::size_t checked = 0, traceable = 0, plain = 0, differ = 0;
    // Groups at every offset modulo the width, so that each ray sits in every lane, and partial
    // groups of every size.
    for (std::size_t shift = 0; shift < lanes<P>; ++shift) {
        for (std::size_t base = shift; base < rays.size(); base += lanes<P>) {
            const std::size_t count = std::min(lanes<P> - (base / lanes<P>) % lanes<P>, rays.size() - base);
            const std::span<const Ray> in(rays.data() + base, std::max<std::size_t>(count, 1));
            wide_ray_setup(in, setup);
            for (std::size_t i = 0; i < in.size(); ++i) {
                WideRay<P> got;
                setup.get(i, got);
                const WideRay<P> want = wide_ray<P>(in[i].org, in[i].dir, in[i].tnear, in[i].tfar);
                if (!same_ray(got, want)) {
                    ++differ;
                    MESSAGE("ray " << base + i << " lane " << i << " of " << in.size());
                }
                ++checked;
                traceable += want.traceable;
                plain += want.plain;
            }
            // Lanes past the group's rays are never traceable.
            for (std::size_t i = in.size(); i < lanes<P>; ++i) CHECK_FALSE(((setup.traceable >> i) & 1u) != 0);
        }
    }
    CHECK(differ == 0);
    CHECK(checked >= rays.size());
    CHECK(traceable < checked);  // untraceable rays were in the groups
    CHECK(plain < traceable);    // and rays that are not plain
    CHECK(plain > checked / 2);
}
