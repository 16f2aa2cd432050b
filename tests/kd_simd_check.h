#pragma once
/// Checks of the kd-tree's SIMD paths (accel/kdtree/kdtree_simd.h): every path is bit-identical to the
/// kd-tree's scalar path (t, prim, u, v), closest and any hit, in several settings (block width,
/// packet lanes, switch threshold) made from one built tree.
#include "accel/kdtree/kdtree_accel.h"
#include "accel/wide/wide_paths.h"
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

/// Settings of the SIMD paths to check: block widths 8 and 16 (when the build has AVX-512),
/// packets of 8 and 16 lanes, switch thresholds 0 (always together), 1 and 3.
inline std::vector<accel::BuildConfig> kd_simd_configs() {
    std::vector<accel::BuildConfig> out;
    const bool has16 = accel::wide_width_supported(16);  // the kernel set in use has AVX-512
    const std::uint32_t blocks[] = {8, 16, 8};
    const std::uint32_t lanes[] = {16, 8, 8};
    const int switches[] = {1, 0, 3};
    for (int i = 0; i < 3; ++i) {
        accel::BuildConfig c;
        c.kd_blocks.width = has16 ? blocks[i] : 8;
        c.packets.lanes = has16 ? lanes[i] : 8;
        c.packets.switch_lanes = switches[i];
        out.push_back(c);
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
/// bitwise equal answers for closest and any hit. Returns the number of path runs compared.
inline std::size_t check_kd_simd(const accel::KdTreeAccel& kd, const std::vector<Ray>& rays,
                                 std::vector<std::size_t> chunks = {1024}) {
    std::vector<Hit> closest(rays.size()), any(rays.size());
    kd.trace(rays, closest, {accel::Query::closest, accel::TracePath::scalar});
    kd.trace(rays, any, {accel::Query::any, accel::TracePath::scalar});
    std::size_t runs = 0;
    const auto compare = [&](const std::vector<Hit>& got, bool any_hit, const std::string& what) {
        const std::vector<Hit>& ref = any_hit ? any : closest;
        std::size_t bad = 0, first_bad = rays.size();
        for (std::size_t i = 0; i < rays.size(); ++i)
            if (!same_hit(got[i], ref[i])) {
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
        for (const std::size_t chunk : chunks)
            for (const auto path : {accel::TracePath::single, accel::TracePath::packet})
                for (const bool any_hit : {false, true}) {
                    const std::string what = std::string(accel::to_string(path)) + (any_hit ? " any" : " closest") +
                                             " block " + std::to_string(paths->simd_block_width()) + " lanes " +
                                             std::to_string(paths->offer().packet_lanes) + " switch " +
                                             std::to_string(cfg.packets.switch_lanes) + " chunk " + std::to_string(chunk);
                    compare(kd_simd_trace(*paths, rays, path, any_hit, chunk), any_hit, what);
                }
    }
    return runs;
}

}  // namespace arbor::testing
