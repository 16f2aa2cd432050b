#pragma once
/// Helpers of the SIMD-path tests: every BVH structure (bvh-median, bvh-sah, lbvh) at every width
/// this build has, built from one binary tree per structure, and the check of every traversal path
/// against the scalar path and brute.
#include "accel/dispatch/kernel_entries.h"
#include "accel/factory/make_accel.h"
#include "accel/structures/brute_accel.h"
#include "accel/structures/bvh_accel.h"
#include "accel/bvh/bvh_build.h"
#include "accel/lbvh/lbvh_build.h"
#include "accel/interface/trace.h"
#include "accel/structures/wide_paths.h"
#include "bvh_check.h"
#include "simd/ray_triangle.h"

#include <doctest/doctest.h>

#include <cstring>
#include <memory>
#include <string>
#include <vector>

namespace arbor::testing {

struct BuiltBvh {
    std::string name;  ///< "bvh-sah/w16"
    std::unique_ptr<accel::Accel> accel;
};

/// The widths this build can trace.
inline std::vector<std::uint32_t> wide_widths() {
    std::vector<std::uint32_t> w;
    for (std::uint32_t n : {4u, 8u, 16u})
        if (accel::wide_width_supported(n)) w.push_back(n);
    return w;
}

/// bvh-median, bvh-sah and lbvh over `v`, each at every width (one binary build per structure,
/// collapsed once per width). `widths` empty = all of wide_widths(). The packet settings rotate so
/// that every width meets 8- and 16-lane packets (when the build has them) and switch thresholds of
/// 0 (never single rays), 1 and 3 lanes, and for packets of mixed octants 0, the default (lanes / 2)
/// and 16 (single rays from the root).
inline std::vector<BuiltBvh> all_wide_bvhs(const accel::TriangleView& v, accel::BuildConfig cfg = {},
                                           std::vector<std::uint32_t> widths = {}) {
    if (widths.empty()) widths = wide_widths();
    struct Kind {
        accel::AccelKind kind;
        accel::BvhBuilder build;
        const char* name;
    };
    const Kind kinds[] = {{accel::AccelKind::bvh_median, accel::build_bvh_median, "bvh-median"},
                          {accel::AccelKind::bvh_sah, accel::build_bvh_sah, "bvh-sah"},
                          {accel::AccelKind::lbvh, accel::build_lbvh, "lbvh"}};
    std::vector<BuiltBvh> out;
    const accel::PrimRefs refs = accel::make_prim_refs(v);
    const bool has16 = accel::wide_width_supported(16);
    int turn = 0;
    for (const Kind& k : kinds) {
        const accel::BinaryBvh bvh = k.build(refs, cfg.bvh);
        for (const std::uint32_t w : widths) {
            cfg.wide.width = w;
            cfg.packets.lanes = has16 && turn % 2 == 0 ? 16 : 8;
            cfg.packets.switch_lanes = (turn / 2) % 3 == 2 ? 3 : (turn / 2) % 3;
            cfg.packets.switch_mixed = turn % 3 == 0 ? 0 : turn % 3 == 1 ? -1 : 16;
            ++turn;
            accel::BinaryBvh copy = bvh;
            out.push_back({std::string(k.name) + "/w" + std::to_string(w) + "/p" + std::to_string(cfg.packets.lanes) + "s" +
                               std::to_string(cfg.packets.switch_lanes) + "x" + std::to_string(cfg.packets.switch_mixed),
                           accel::make_bvh_accel(k.kind, std::move(copy), v, cfg, 0.0)});
        }
    }
    return out;
}

/// The paths to check besides scalar: single, packet (when the structure has it) and best.
inline std::vector<accel::TracePath> simd_paths(const accel::Accel& a) {
    std::vector<accel::TracePath> p;
    for (const auto path : {accel::TracePath::single, accel::TracePath::packet})
        if (a.offer().has(path)) p.push_back(path);
    p.push_back(accel::TracePath::best);  // always asked: the policy picks one the structure has
    return p;
}

/// Every SIMD path of `a` against its scalar path on all `rays`, and against brute's closest hits
/// `ref` on the rays listed in `sample` (ref[k] answers rays[sample[k]]), over the triangles `tris`
/// the structure was built on. Closest hit: the whole record, bit for bit (t, prim, u, v: every
/// path runs the same watertight test and the same tie rule, accel/core/hit_record.h). Any hit: a
/// hit exactly when the scalar path finds one, and the named triangle really occludes the ray: its
/// own scalar test hits it at exactly the reported t, u, v within [tnear, tfar]. Which occluder an
/// any-hit query names may legitimately differ between paths (it stops at the first found, and
/// the SIMD paths visit leaves in another order: 31-627 of 131072 shadow rays of the benchmark
/// files name another one than the scalar path). `chunk` is trace_parallel's chunk (small chunks:
/// partial packets). Returns the number of paths checked.
inline std::size_t check_paths(const accel::Accel& a, const accel::TriangleView& tris, const std::vector<Ray>& rays,
                               const std::vector<std::size_t>& sample, const std::vector<Hit>& ref,
                               std::size_t chunk = 1024) {
    std::vector<Hit> scalar(rays.size()), got(rays.size()), any(rays.size());
    accel::trace_parallel(a, rays, scalar, accel::Query::closest, accel::TracePath::scalar, chunk);
    const auto same = [](const Hit& x, const Hit& y) { return std::memcmp(&x, &y, sizeof(Hit)) == 0; };
    // Against brute: the whole record too, except that the kd-tree may name another triangle at
    // exactly the same t (a tie across a split plane: its walk stops after the leaf that holds the
    // hit, so a tied triangle with a lower id in the next leaf is not seen); counted apart, bounded
    // to the kd-tree, and never allowed on a BVH.
    const auto tie = [](const Hit& x, const Hit& y) { return x.is_hit() && y.is_hit() && x.t == y.t && x.prim != y.prim; };
    const bool ties_allowed = a.kind() == accel::AccelKind::kdtree;
    std::size_t bad_scalar_brute = 0, tie_scalar_brute = 0;
    for (std::size_t k = 0; k < sample.size(); ++k) {
        const bool t = tie(ref[k], scalar[sample[k]]);
        tie_scalar_brute += t;
        bad_scalar_brute += !t && !same(ref[k], scalar[sample[k]]);
    }
    CHECK(bad_scalar_brute == 0);
    CHECK((ties_allowed || tie_scalar_brute == 0));
    CHECK(tie_scalar_brute <= sample.size() / 100);
    std::size_t checked = 0;
    for (const accel::TracePath path : simd_paths(a)) {
        CAPTURE(accel::to_string(path));
        accel::trace_parallel(a, rays, got, accel::Query::closest, path, chunk);
        accel::trace_parallel(a, rays, any, accel::Query::any, path, chunk);
        std::size_t bad = 0, bad_any = 0, not_occluder = 0, bad_brute = 0, first_bad = rays.size();
        for (std::size_t i = 0; i < rays.size(); ++i) {
            if (!same(scalar[i], got[i]) && bad++ == 0) first_bad = i;
            bad_any += any[i].is_hit() != scalar[i].is_hit();
            if (!any[i].is_hit()) continue;
            const Ray& r = rays[i];
            const std::uint32_t p = any[i].prim;
            bool occludes = p < tris.triangle_count();
            if (occludes) {
                const simd::TriHit<float> h = simd::woop_test(r.org, simd::woop_shear(r.dir), r.tnear, r.tfar,
                                                              tris.corner(p, 0), tris.corner(p, 1), tris.corner(p, 2));
                occludes = h.hit && h.t == any[i].t && h.u == any[i].u && h.v == any[i].v && h.t >= r.tnear &&
                           h.t <= r.tfar;
            }
            not_occluder += !occludes;
        }
        for (std::size_t k = 0; k < sample.size(); ++k)
            bad_brute += !same(ref[k], got[sample[k]]) && !(ties_allowed && tie(ref[k], got[sample[k]]));
        CAPTURE(first_bad);
        CHECK(bad == 0);
        CHECK(bad_any == 0);
        CHECK(not_occluder == 0);
        CHECK(bad_brute == 0);
        ++checked;
    }
    return checked;
}

/// check_paths with brute on every ray.
inline std::size_t check_paths(const accel::Accel& a, const accel::TriangleView& tris, const std::vector<Ray>& rays,
                               const std::vector<Hit>& ref, std::size_t chunk = 1024) {
    std::vector<std::size_t> all(rays.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
    return check_paths(a, tris, rays, all, ref, chunk);
}

}  // namespace arbor::testing
