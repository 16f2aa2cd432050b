// The SIMD kernel sets (accel/dispatch/kernel_set.h, kernel_table.h): the set in use is the one
// ARBOR_ISA forces or the widest the CPU supports, a bad ARBOR_ISA is refused in one line, and every
// set the build holds and the CPU runs (all three in a portable build) gives the scalar path's
// answers bit for bit (t, prim, u, v; any hit on a BVH: hit or miss) on its wide BVHs and kd-tree, called through each set's own
// table in this one process. The portable build also runs the agreement suites with each set
// forced (tests/CMakeLists.txt, kernel_set_*).
#include "accel/dispatch/kernel_entries.h"
#include "accel/factory/make_accel.h"
#include "accel/structures/bvh_accel.h"
#include "accel/bvh/bvh_build.h"
#include "accel/dispatch/kernel_set.h"
#include "accel/dispatch/kernel_table.h"
#include "accel/structures/kdtree_accel.h"
#include "engine/procedural.h"
#include "testing.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

using namespace arbor;

namespace {

bool built(std::string_view set) {
    const auto sets = accel::kernel_sets_built();
    return std::find(sets.begin(), sets.end(), set) != sets.end();
}

/// The sets this process can run: every set built, less those a portable build's CPU lacks.
std::vector<const accel::KernelTable*> runnable_sets() {
    std::vector<const accel::KernelTable*> out;
    for (const std::string_view set : accel::kernel_sets_built()) {
        if (accel::kernel_sets_built().size() > 1 && !accel::cpu_supports_kernel_set(set)) continue;
        out.push_back(&accel::choose_kernels(std::string(set).c_str()));
    }
    return out;
}

/// Rays whose hits differ: closest hit, the whole record; any hit, whether it hit (a BVH's any hit
/// may name another occluder than the scalar walk's; the kd-tree's is the first in walk order on
/// every path, so its record is compared whole).
std::size_t differences(const std::vector<accel::Hit>& a, const std::vector<accel::Hit>& b, bool whole) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
        n += whole ? std::memcmp(&a[i], &b[i], sizeof(accel::Hit)) != 0 : a[i].is_hit() != b[i].is_hit();
    return n;
}

}  // namespace

TEST_CASE("kernel set: the set in use is the one ARBOR_ISA forces, else the widest the CPU runs") {
    const std::string set(accel::kernel_set());
    CHECK(built(set));
    const char* forced = std::getenv("ARBOR_ISA");
    if (forced != nullptr && *forced != '\0') CHECK(set == forced);
    else CHECK(set == accel::choose_kernels(nullptr).name);
    // The widths the set in use offers are its own.
    CHECK(accel::wide_width_supported(4));
    CHECK(accel::wide_width_supported(8) == (set != "sse4"));
    CHECK(accel::wide_width_supported(16) == (set == "avx512"));
    CHECK(accel::default_wide_width() == (set == "avx512" ? 16u : set == "avx2" ? 8u : 4u));
    CHECK(accel::kernel_set_skipped().empty() == (set == "avx512"));
}

TEST_CASE("kernel set: an unknown, absent or unsupported ARBOR_ISA is refused with one line") {
    CHECK_THROWS_WITH_AS(accel::choose_kernels("avx1024"),
                         "ARBOR_ISA=avx1024: unknown SIMD kernel set (expected sse4, avx2 or avx512)", std::runtime_error);
    CHECK(std::string(accel::choose_kernels("").name) == accel::choose_kernels(nullptr).name);
    const bool portable = accel::kernel_sets_built().size() > 1;
    for (const char* set : {"sse4", "avx2", "avx512"}) {
        CAPTURE(set);
        if (built(set) && (!portable || accel::cpu_supports_kernel_set(set))) {
            CHECK(std::string(accel::choose_kernels(set).name) == set);
        } else {
            try {
                accel::choose_kernels(set);
                FAIL("no error for a set that is absent or unsupported");
            } catch (const std::runtime_error& e) {
                const std::string what = e.what();
                CHECK(what.rfind(std::string("ARBOR_ISA=") + set + ": ", 0) == 0);
                CHECK(what.find('\n') == std::string::npos);
            }
        }
    }
}

TEST_CASE("kernel set: every set the CPU runs gives the scalar path's hits bit for bit") {
    // (The hits through each set's own table: a portable build's are three different compilations.)
    const engine::Mesh mesh = engine::make_icosphere({0.0f, 0.0f, 0.0f}, 1.0f, 3, 0.05f, 7);
    const accel::TriangleView view = mesh.view();
    const std::vector<accel::Ray> rays = testing::three_kinds(mesh.bounds, 1500, 17);
    accel::BuildConfig cfg;
    const accel::BinaryBvh bvh = accel::build_bvh_sah(accel::make_prim_refs(view), cfg.bvh);
    const auto kd = accel::make_kdtree_accel(view, cfg);
    const auto sets = runnable_sets();
    CHECK(!sets.empty());
    for (const accel::KernelTable* set : sets) {
        for (const std::uint32_t width : {4u, 8u, 16u}) {
            accel::BuildConfig c = cfg;
            c.wide.width = width;
            c.packets.lanes = width == 4 ? 0 : width;
            const auto wide = set->make_wide_bvh_accel(accel::AccelKind::bvh_sah, bvh, view, c, 0.0);
            const auto k = set->make_kd_simd_accel(kd->tree(), c, 0.0);
            for (const accel::Accel* a : {static_cast<const accel::Accel*>(wide.get()), static_cast<const accel::Accel*>(k.get())}) {
                for (const auto query : {accel::Query::closest, accel::Query::any}) {
                    std::vector<accel::Hit> ref(rays.size());
                    a->trace(rays, ref, {query, accel::TracePath::scalar});
                    for (const auto path : {accel::TracePath::single, accel::TracePath::packet}) {
                        const bool kd = a != wide.get();
                        const std::string what = std::string(set->name) + (kd ? " kdtree" : " bvh-sah") + " width " +
                                                 std::to_string(width) + " " + std::string(accel::to_string(path)) +
                                                 (query == accel::Query::any ? " any" : " closest");
                        CAPTURE(what);
                        std::vector<accel::Hit> got(rays.size());
                        a->trace(rays, got, {query, path});
                        CHECK(differences(got, ref, kd || query == accel::Query::closest) == 0);
                    }
                }
            }
        }
    }
}
