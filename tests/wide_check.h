#pragma once
/// Helpers of the SIMD-path tests: every BVH structure (bvh-median, bvh-sah, lbvh) at every width
/// this build has, built from one binary tree per structure, and the check of every traversal path
/// against the scalar path and brute.
#include "accel/brute/brute_accel.h"
#include "accel/bvh/bvh_accel.h"
#include "accel/bvh/bvh_build.h"
#include "accel/lbvh/lbvh_build.h"
#include "accel/trace.h"
#include "accel/wide/wide_paths.h"
#include "bvh_check.h"

#include <doctest/doctest.h>

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
        const accel::BinaryBvh bvh = k.build(refs, cfg);
        for (const std::uint32_t w : widths) {
            cfg.bvh_width = w;
            cfg.packet_lanes = has16 && turn % 2 == 0 ? 16 : 8;
            cfg.packet_switch = (turn / 2) % 3 == 2 ? 3 : (turn / 2) % 3;
            cfg.packet_switch_mixed = turn % 3 == 0 ? 0 : turn % 3 == 1 ? -1 : 16;
            ++turn;
            accel::BinaryBvh copy = bvh;
            out.push_back({std::string(k.name) + "/w" + std::to_string(w) + "/p" + std::to_string(cfg.packet_lanes) + "s" +
                               std::to_string(cfg.packet_switch) + "x" + std::to_string(cfg.packet_switch_mixed),
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

/// Every SIMD path of `a` against its scalar path on all `rays` (closest hits by the rayfile.md
/// rule; any hit: a hit exactly when the scalar path's closest hit exists, with t in [tnear, tfar])
/// and against brute's closest hits `ref` on the rays listed in `sample` (ref[k] answers
/// rays[sample[k]]). `chunk` is trace_parallel's chunk (small chunks: partial packets). Returns the
/// number of paths checked.
inline std::size_t check_paths(const accel::Accel& a, const std::vector<Ray>& rays, const std::vector<std::size_t>& sample,
                               const std::vector<Hit>& ref, std::size_t chunk = 1024) {
    std::vector<Hit> scalar(rays.size()), got(rays.size()), any(rays.size());
    accel::trace_parallel(a, rays, scalar, accel::Query::closest, accel::TracePath::scalar, chunk);
    std::size_t checked = 0;
    for (const accel::TracePath path : simd_paths(a)) {
        CAPTURE(accel::to_string(path));
        accel::trace_parallel(a, rays, got, accel::Query::closest, path, chunk);
        accel::trace_parallel(a, rays, any, accel::Query::any, path, chunk);
        std::size_t bad = 0, bad_any = 0, out_of_range = 0, bad_brute = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            bad += !accel::hits_agree(scalar[i], got[i]);
            bad_any += any[i].is_hit() != scalar[i].is_hit();
            if (any[i].is_hit()) out_of_range += !(any[i].t >= rays[i].tnear && any[i].t <= rays[i].tfar);
        }
        for (std::size_t k = 0; k < sample.size(); ++k) bad_brute += !accel::hits_agree(ref[k], got[sample[k]]);
        CHECK(bad == 0);
        CHECK(bad_any == 0);
        CHECK(out_of_range == 0);
        CHECK(bad_brute == 0);
        ++checked;
    }
    return checked;
}

/// check_paths with brute on every ray.
inline std::size_t check_paths(const accel::Accel& a, const std::vector<Ray>& rays, const std::vector<Hit>& ref,
                               std::size_t chunk = 1024) {
    std::vector<std::size_t> all(rays.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
    return check_paths(a, rays, all, ref, chunk);
}

}  // namespace arbor::testing
