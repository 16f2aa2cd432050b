#pragma once
/// Oracle comparison for the kd-tree tests: closest and any hit against `brute`.
#include "accel/factory/make_accel.h"
#include "accel/structures/brute_accel.h"
#include "accel/structures/kdtree_accel.h"
#include "kd_simd_check.h"
#include "simd/ray_triangle.h"
#include "testing.h"

#include <doctest/doctest.h>

#include <cstring>

namespace arbor::testing {

struct OracleResult {
    std::size_t rays = 0, hits = 0;
    std::size_t closest_bad = 0;  ///< closest hits disagreeing by the rayfile.md rule
    std::size_t closest_not_identical = 0;  ///< closest hits not bit-identical to brute's (t, prim, u, v): the tie rule
    std::size_t any_bad = 0;      ///< any-hit answers that are not a real hit exactly when brute hits
};

/// Traces `rays` through `kd` and `brute`; an any-hit answer must hit iff brute does, and its
/// (t, prim) must be a real hit of that triangle in [tnear, tfar] (re-checked with the watertight test).
inline OracleResult compare_with_brute(const accel::KdTreeAccel& kd, const accel::BruteAccel& brute,
                                       const accel::TriangleView& view, const std::vector<Ray>& rays) {
    OracleResult r;
    r.rays = rays.size();
    std::vector<Hit> a(rays.size()), b(rays.size()), any(rays.size());
    kd.trace(rays, a, {accel::Query::closest, accel::TracePath::scalar});
    brute.trace(rays, b, {accel::Query::closest, accel::TracePath::scalar});
    kd.trace(rays, any, {accel::Query::any, accel::TracePath::scalar});
    for (std::size_t i = 0; i < rays.size(); ++i) {
        r.hits += b[i].is_hit();
        r.closest_bad += !accel::hits_agree(a[i], b[i]);
        r.closest_not_identical += std::memcmp(&a[i], &b[i], sizeof(Hit)) != 0;
        bool ok = any[i].is_hit() == b[i].is_hit();
        if (ok && any[i].is_hit()) {
            const Ray& ray = rays[i];
            const auto h = simd::woop_test(ray.org, simd::woop_shear(ray.dir), ray.tnear, ray.tfar,
                                           view.corner(any[i].prim, 0), view.corner(any[i].prim, 1),
                                           view.corner(any[i].prim, 2));
            ok = h.hit && h.t == any[i].t;
        }
        r.any_bad += !ok;
    }
    return r;
}

/// Builds both structures over `mesh` and requires full agreement on `rays`; the kd-tree's SIMD
/// paths must give the scalar path's answers bit for bit (kd_simd_check.h).
inline void require_agreement(const engine::Mesh& mesh, const std::vector<Ray>& rays,
                              const accel::BuildConfig& cfg = {}) {
    const auto kd_built = accel::make_kdtree_accel(mesh.view(), cfg);
    const accel::KdTreeAccel& kd = *kd_built;
    const accel::BruteAccel brute(mesh.view());
    const OracleResult r = compare_with_brute(kd, brute, mesh.view(), rays);
    CAPTURE(r.rays);
    CAPTURE(r.hits);
    CHECK(r.closest_bad == 0);
    CHECK(r.closest_not_identical == 0);
    CHECK(r.any_bad == 0);
    CHECK(check_kd_simd(kd, rays) > 0);
}

}  // namespace arbor::testing
