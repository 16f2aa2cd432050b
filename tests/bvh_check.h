#pragma once
/// Helpers of the BVH tests: build a structure by name, compare it with brute on a set of rays.
#include "accel/interface/accel.h"
#include "accel/structures/brute_accel.h"
#include "accel/structures/bvh_accel.h"
#include "accel/bvh/bvh_build.h"
#include "accel/interface/trace.h"
#include "engine/mesh.h"
#include "testing.h"

#include <doctest/doctest.h>

#include <string>
#include <vector>

namespace arbor::testing {

/// Brute force costs rays x triangles; sanitizer builds run ~10x slower, so they get a smaller budget.
#if defined(ARBOR_SANITIZED_BUILD)
inline constexpr double brute_budget = 6e5;
#else
inline constexpr double brute_budget = 6e6;
#endif

/// Rays per kind for a mesh of `triangles` under the brute budget, at least `floor`.
inline std::size_t oracle_ray_count(std::size_t triangles, std::size_t floor = 64, std::size_t cap = 3000) {
    const double n = brute_budget / double(std::max<std::size_t>(triangles, 1));
    return std::clamp(std::size_t(n), floor, cap);
}

/// The BVH kinds this suite covers, with their builders.
struct BvhKind {
    accel::AccelKind kind;
    accel::BvhBuilder builder;
    std::string name;
};
inline const std::vector<BvhKind>& bvh_kinds() {
    static const std::vector<BvhKind> kinds = {{accel::AccelKind::bvh_median, accel::build_bvh_median, "bvh-median"},
                                               {accel::AccelKind::bvh_sah, accel::build_bvh_sah, "bvh-sah"}};
    return kinds;
}

/// Brute force's closest hits for `rays` (traced in parallel): the reference of check_oracle.
inline std::vector<Hit> brute_answers(const accel::BruteAccel& brute, const std::vector<Ray>& rays) {
    std::vector<Hit> ref(rays.size());
    accel::trace_parallel(brute, rays, ref, accel::Query::closest, accel::TracePath::scalar, 16);
    return ref;
}

/// Closest and any hit of `accel` against brute's closest hits `ref` for the same rays: every
/// answer agrees per rayfile.md, any-hit reports a hit exactly when brute does, and an any-hit t
/// lies in the ray's [tnear, tfar]. Returns how many rays hit (for the caller to check that the
/// rays test something).
inline std::size_t check_oracle(const accel::Accel& accel, const std::vector<Ray>& rays, const std::vector<Hit>& ref) {
    std::vector<Hit> got(rays.size()), any(rays.size());
    accel::trace_parallel(accel, rays, got, accel::Query::closest, accel::TracePath::scalar, 64);
    accel::trace_parallel(accel, rays, any, accel::Query::any, accel::TracePath::scalar, 64);
    std::size_t bad = 0, bad_any = 0, out_of_range = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        bad += !accel::hits_agree(ref[i], got[i]);
        bad_any += any[i].is_hit() != ref[i].is_hit();
        if (any[i].is_hit()) out_of_range += !(any[i].t >= rays[i].tnear && any[i].t <= rays[i].tfar);
    }
    CHECK(bad == 0);
    CHECK(bad_any == 0);
    CHECK(out_of_range == 0);
    return std::size_t(std::count_if(ref.begin(), ref.end(), [](const Hit& h) { return h.is_hit(); }));
}

}  // namespace arbor::testing
