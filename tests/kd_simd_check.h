#pragma once
/// Checks of the kd-tree's SIMD paths (accel/structures/kdtree_simd.h): every path is bit-identical to the
/// kd-tree's scalar path (t, prim, u, v), closest and any hit, in several settings (block width,
/// packet lanes, switch threshold) made from one built tree.
#include "accel/dispatch/kernel_entries.h"
#include "accel/factory/make_accel.h"
#include "accel/structures/kdtree_accel.h"
#include "accel/structures/wide_paths.h"
#include "simd/ray_triangle.h"
#include "testing.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

namespace arbor::testing {

/// Bitwise equality of two hit records.
inline bool same_hit(const accel::Hit& a, const accel::Hit& b) { return std::memcmp(&a, &b, sizeof(accel::Hit)) == 0; }

/// Settings of the SIMD paths to check. The rope walks (KdWalk::ropes): block widths 8 and 16
/// (when the build has AVX-512), packets of 8 and 16 lanes, switch thresholds 0 (always together),
/// 1 and 3. The cell walks (KdWalk::cells and tight_cells): the wide widths the build can trace
/// (16, 8, 4) with packets of 16 and 8 lanes.
inline std::vector<accel::BuildConfig> kd_simd_configs() {
    std::vector<accel::BuildConfig> out;
    const bool has16 = accel::wide_width_supported(16);  // the kernel set in use has AVX-512
    const std::uint32_t blocks[] = {8, 16, 8};
    const std::uint32_t lanes[] = {16, 8, 8};
    const int switches[] = {1, 0, 3};
    for (int i = 0; i < 3; ++i) {
        accel::BuildConfig c;
        c.kd_blocks.walk = accel::KdWalk::ropes;
        c.kd_blocks.width = has16 ? blocks[i] : 8;
        c.packets.lanes = has16 ? lanes[i] : 8;
        c.packets.switch_lanes = switches[i];
        out.push_back(c);
    }
    const std::uint32_t widths[] = {16, 8, 4};
    for (int i = 0; i < 3; ++i)
        for (const accel::KdWalk walk : {accel::KdWalk::tight_cells, accel::KdWalk::cells}) {
            if (!accel::wide_width_supported(widths[i])) continue;
            accel::BuildConfig c;
            c.kd_blocks.walk = walk;
            c.wide.width = widths[i];
            c.packets.lanes = has16 && i == 0 ? 16 : 8;
            out.push_back(c);
        }
    return out;
}

/// Whether `got` answers an any-hit query as the cell walk must (the BVHs' contract, wide_check.h):
/// a hit exactly when `ref` (the scalar path's any hit) is one, naming a triangle of `tree` whose
/// own watertight test hits `ray` at exactly the reported t, u, v within [tnear, tfar]. (The cell
/// walk visits the cells in another order than the scalar stack walk: it may name another occluder.)
inline bool any_hit_ok(const accel::KdTree& tree, const std::vector<std::uint32_t>& tri_of_prim, const Ray& ray,
                       const Hit& got, const Hit& ref) {
    if (got.is_hit() != ref.is_hit()) return false;
    if (!got.is_hit()) return true;
    if (got.prim >= tri_of_prim.size() || tri_of_prim[got.prim] == accel::invalid_prim) return false;
    const accel::KdTriangle& t = tree.tris[tri_of_prim[got.prim]];
    const simd::TriHit<float> h = simd::woop_test(ray.org, simd::woop_shear(ray.dir), ray.tnear, ray.tfar, t.v0, t.v1, t.v2);
    return h.hit && h.t == got.t && h.u == got.u && h.v == got.v && h.t >= ray.tnear && h.t <= ray.tfar;
}

/// tree.tris index of each prim (invalid_prim: not in the tree).
inline std::vector<std::uint32_t> kd_tri_of_prim(const accel::KdTree& tree) {
    std::vector<std::uint32_t> out;
    for (std::uint32_t i = 0; i < tree.tris.size(); ++i) {
        if (tree.tris[i].prim >= out.size()) out.resize(tree.tris[i].prim + 1, accel::invalid_prim);
        out[tree.tris[i].prim] = i;
    }
    return out;
}

/// The rays through `kd` on `path` in chunks of `chunk` rays (chunk boundaries make partial packets).
inline std::vector<Hit> kd_simd_trace(const accel::KdTreeAccel& kd, const std::vector<Ray>& rays, accel::TracePath path,
                                      bool any_hit, std::size_t chunk) {
    REQUIRE(kd.offer().has(path));
    std::vector<Hit> hits(rays.size());
    for (std::size_t base = 0; base < rays.size(); base += chunk) {
        const std::size_t n = std::min(chunk, rays.size() - base);
        kd.trace(std::span(rays).subspan(base, n), std::span(hits).subspan(base, n),
                 {any_hit ? accel::Query::any : accel::Query::closest, path});
    }
    return hits;
}

/// Every SIMD path of `kd` (as built, then in each of kd_simd_configs()) against its scalar path:
/// bitwise equal answers for closest hit; for any hit bitwise equal on the rope walks (they visit
/// the scalar stack walk's leaves in its order), the any-hit contract (any_hit_ok) on the cell
/// walks. Returns the number of path runs compared.
inline std::size_t check_kd_simd(const accel::KdTreeAccel& kd, const std::vector<Ray>& rays,
                                 std::vector<std::size_t> chunks = {1024}) {
    std::vector<Hit> closest(rays.size()), any(rays.size());
    kd.trace(rays, closest, {accel::Query::closest, accel::TracePath::scalar});
    kd.trace(rays, any, {accel::Query::any, accel::TracePath::scalar});
    const std::vector<std::uint32_t> tri_of_prim = kd_tri_of_prim(kd.tree());
    std::size_t runs = 0;
    accel::KdWalk walk = kd.walk();  // of the paths compared
    const auto compare = [&](const std::vector<Hit>& got, bool any_hit, const std::string& what) {
        const std::vector<Hit>& ref = any_hit ? any : closest;
        const bool contract = any_hit && walk != accel::KdWalk::ropes;
        std::size_t bad = 0, first_bad = rays.size();
        for (std::size_t i = 0; i < rays.size(); ++i)
            if (contract ? !any_hit_ok(kd.tree(), tri_of_prim, rays[i], got[i], ref[i]) : !same_hit(got[i], ref[i])) {
                if (bad++ == 0) first_bad = i;
            }
        CAPTURE(what);
        CAPTURE(first_bad);
        CHECK(bad == 0);
        ++runs;
    };
    // As built, through the Accel interface (best included).
    for (const auto path : {accel::TracePath::single, accel::TracePath::packet, accel::TracePath::best}) {
        std::vector<Hit> got(rays.size());
        kd.trace(rays, got, {accel::Query::closest, path});
        compare(got, false, "accel closest " + std::string(accel::to_string(path)));
        kd.trace(rays, got, {accel::Query::any, path});
        compare(got, true, "accel any " + std::string(accel::to_string(path)));
    }
    // The packet walk takes only lanes that share a direction octant (at least half a packet); the
    // rays again, ordered by octant, so that every stiff and degenerate ray is walked in a packet.
    std::vector<std::size_t> by_octant(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) by_octant[i] = i;
    const auto octant = [&](std::size_t i) {
        const Vec3f& d = rays[i].dir;
        return int(std::signbit(d.x)) | int(std::signbit(d.y)) << 1 | int(std::signbit(d.z)) << 2;
    };
    std::stable_sort(by_octant.begin(), by_octant.end(), [&](std::size_t a, std::size_t b) { return octant(a) < octant(b); });
    std::vector<Ray> sorted(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) sorted[i] = rays[by_octant[i]];
    for (const bool any_hit : {false, true}) {
        std::vector<Hit> got(rays.size()), back(rays.size());
        kd.trace(sorted, got, {any_hit ? accel::Query::any : accel::Query::closest, accel::TracePath::packet});
        for (std::size_t i = 0; i < rays.size(); ++i) back[by_octant[i]] = got[i];
        compare(back, any_hit, any_hit ? "packet any, rays by octant" : "packet closest, rays by octant");
    }
    for (const accel::BuildConfig& cfg : kd_simd_configs()) {
        const auto paths = accel::make_kdtree_accel(kd.tree(), cfg);  // a copy of the tree, other settings
        walk = paths->walk();
        CHECK(walk == cfg.kd_blocks.walk);
        for (const std::size_t chunk : chunks)
            for (const auto path : {accel::TracePath::single, accel::TracePath::packet})
                for (const bool any_hit : {false, true}) {
                    const std::string what = std::string(accel::to_string(path)) + (any_hit ? " any" : " closest") +
                                             " " + accel::kd_walk_name(walk) + " block " +
                                             std::to_string(paths->simd_block_width()) + " lanes " +
                                             std::to_string(paths->offer().packet_lanes) + " switch " +
                                             std::to_string(cfg.packets.switch_lanes) + " chunk " + std::to_string(chunk);
                    compare(kd_simd_trace(*paths, rays, path, any_hit, chunk), any_hit, what);
                }
    }
    return runs;
}

}  // namespace arbor::testing
