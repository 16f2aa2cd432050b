// Resource limits: byte sizes as people write them, and input that would not fit in memory is
// refused with a one-line error before anything is allocated (ray files whose header matches a
// huge file, OBJ files larger than the budget).
#include "accel/bvh/bvh2_layout.h"
#include "accel/bvh/bvh_build.h"
#include "accel/bvh/build_prims.h"
#include "accel/bvh/prim_refs.h"
#include "accel/factory/make_accel.h"
#include "accel/lbvh/lbvh_build.h"
#include "accel/factory/memory_estimate.h"
#include "engine/error.h"
#include "engine/file_io.h"
#include "engine/memory_budget.h"
#include "engine/obj_loader.h"
#include "engine/procedural.h"
#include "engine/rayfile.h"
#include "testing.h"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

using namespace arbor;

namespace {
std::string temp_path(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("arbor_test_mem_" + name)).string();
}
/// What f throws as an E (an input error by default), or "no error".
template <class E = engine::InputError, class F> std::string error_of(F&& f) {
    try {
        f();
    } catch (const E& e) {
        return e.what();
    }
    return "no error";
}

/// Chains of small triangles at x = 1, 2, 4, ... 2^59, each chain a row: a builder that splits by
/// position peels them off one or a few at a time, so with one triangle per binary leaf
/// (--leaf-size 1 --simd-leaf-floor 1) the SIMD layout is mostly one-triangle leaves, one block each.
engine::Mesh peeling_chains(int chains, int per_chain) {
    engine::Mesh m;
    for (int c = 0; c < chains; ++c)
        for (int k = 0; k < per_chain; ++k) {
            const float x = std::ldexp(1.0f, k), s = x * 1e-3f, y = 3.0f * float(c);
            const auto a = m.add_vertex({x, y, 0}), b = m.add_vertex({x + s, y, 0}), d = m.add_vertex({x, y + s, s});
            m.add_triangle(a, b, d);
        }
    return m;
}
/// The three BVH builders, each with the structure it builds.
struct BvhBuilder {
    accel::AccelKind kind;
    accel::BvhPrimBuilder build;
};
const BvhBuilder bvh_builders[] = {{accel::AccelKind::lbvh, accel::build_lbvh},
                                   {accel::AccelKind::bvh_sah, accel::build_bvh_sah},
                                   {accel::AccelKind::bvh_median, accel::build_bvh_median}};

/// Meshes of every shape the build estimates are checked on: subdivided, with a hole, a single
/// triangle and a shared model.
std::vector<engine::Mesh> budget_meshes() {
    std::vector<engine::Mesh> meshes;
    meshes.push_back(engine::make_icosphere({0, 0, 0}, 1.0f, 3, 0.2f, 1));
    meshes.push_back(engine::make_torus({0, 0, 0}, 2.0f, 0.5f, 40, 20));
    engine::Mesh one;
    one.add_vertex({0, 0, 0}), one.add_vertex({1, 0, 0}), one.add_vertex({0, 1, 0});
    one.add_triangle(0, 1, 2);
    meshes.push_back(one);
    engine::Warnings w;
    meshes.push_back(engine::load_obj(testing::shared_scenes_dir() + "/models/spot.obj", w));
    return meshes;
}
}  // namespace

TEST_CASE("memory budget: byte sizes with suffixes") {
    using engine::parse_byte_size;
    CHECK(parse_byte_size("1234") == 1234u);
    CHECK(parse_byte_size("64K") == 65536u);
    CHECK(parse_byte_size("64k") == 65536u);
    CHECK(parse_byte_size("512M") == 512ull << 20);
    CHECK(parse_byte_size("2G") == 2ull << 30);
    CHECK(parse_byte_size("2GB") == 2ull << 30);
    CHECK(parse_byte_size("2GiB") == 2ull << 30);
    CHECK(parse_byte_size("1.5G") == 3ull << 29);
    CHECK(parse_byte_size("1T") == 1ull << 40);
    CHECK(parse_byte_size("7B") == 7u);
    for (const char* bad : {"", "G", "0", "-1G", "2X", "1e3", "abc", "1..5G", "nanG", "20000000000T", "0.1"})
        CHECK_MESSAGE(!parse_byte_size(bad), bad);
    CHECK(engine::format_bytes(812) == "812 B");
    CHECK(engine::format_bytes(3ull << 29) == "1.5 GiB");
    CHECK(engine::physical_memory_bytes() > (64ull << 20));
    CHECK(engine::memory_budget(1000) == 1000u);
    CHECK(engine::memory_budget(0) == engine::physical_memory_bytes());
}

TEST_CASE("memory budget: a ray file larger than memory is refused before allocating") {
    // A sparse file: its header matches its size, 2^40 bytes of rays (1 TiB, no disk used).
    const auto p = temp_path("huge.rays");
    const std::uint64_t n = (1ull << 40) / 32;
    std::string head(16, '\0');
    const std::uint32_t version = 1;
    std::memcpy(head.data(), "RAYS", 4);
    std::memcpy(head.data() + 4, &version, 4);
    std::memcpy(head.data() + 8, &n, 8);
    {
        std::ofstream f(p, std::ios::binary);
        f.write(head.data(), 16);
    }
    std::filesystem::resize_file(p, 16 + (1ull << 40));
    const std::string e = error_of([&] { (void)engine::read_rays(p); });
    CHECK(e.find(p + ": 34359738368 records need 1.0 TiB, more than the ") == 0);
    CHECK(e.find("of memory") != std::string::npos);
    // The same with an explicit budget, on a small valid file.
    std::filesystem::resize_file(p, 16);
    std::string small = head;
    const std::uint64_t ten = 10;
    std::memcpy(small.data() + 8, &ten, 8);
    engine::write_file_atomic(p, small + std::string(320, '\0'));
    CHECK(engine::read_rays(p).size() == 10);
    CHECK(error_of([&] { (void)engine::read_rays(p, 100); }) == p + ": 10 records need 320 B, more than the 100 B of --max-memory");
    CHECK(engine::read_rays(p, 320).size() == 10);
    std::filesystem::remove(p);
}

TEST_CASE("memory budget: an OBJ file too large for the budget is refused before reading") {
    const auto p = temp_path("mesh.obj");
    engine::write_file_atomic(p, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    engine::Warnings w;
    CHECK(engine::load_obj(p, w).triangle_count() == 1);
    CHECK(engine::load_obj(p, w, 1000).triangle_count() == 1);
    CHECK(error_of([&] { (void)engine::load_obj(p, w, 50); }) ==
          p + ": loading 32 B of OBJ text needs about 96 B, more than the 50 B of --max-memory");
    std::filesystem::remove(p);
}

TEST_CASE("memory budget: the build estimate bounds every BVH and brute from above, the kd-tree from below") {
    const std::vector<engine::Mesh> meshes = budget_meshes();
    using accel::AccelKind;
    for (const auto& m : meshes)
        for (AccelKind kind : {AccelKind::brute, AccelKind::bvh_median, AccelKind::bvh_sah, AccelKind::lbvh, AccelKind::kdtree})
            for (std::uint32_t leaf : {1u, 4u, 16u})
                for (std::uint32_t width : {0u, 4u}) {
                    accel::BuildConfig cfg;
                    cfg.bvh.max_leaf_size = leaf;
                    cfg.wide.width = width;
                    const auto a = accel::make_accel(kind, m.view(), cfg);
                    const std::uint64_t estimate = accel::build_memory_estimate(kind, m.triangle_count(), cfg);
                    const std::uint64_t peak = std::max(a->stats().build_peak_bytes, a->stats().memory_bytes);
                    CAPTURE(accel::to_string(kind));
                    CAPTURE(m.triangle_count());
                    CAPTURE(leaf);
                    CAPTURE(width);
                    if (kind == AccelKind::kdtree) CHECK(estimate <= peak);
                    else CHECK(estimate >= peak);
                }
}

TEST_CASE("memory budget: --max-memory refuses a build before it starts, with one line naming the structure") {
    accel::BuildConfig cfg;
    cfg.max_memory = 1ull << 30;
    // From the triangle count alone: a billion triangles need more than 1 GiB for every structure.
    for (auto kind : {accel::AccelKind::brute, accel::AccelKind::bvh_sah, accel::AccelKind::lbvh, accel::AccelKind::kdtree}) {
        CAPTURE(accel::to_string(kind));
        CHECK_THROWS_AS(accel::check_build_memory(kind, 1000000000, cfg), accel::MemoryLimitError);
        CHECK_NOTHROW(accel::check_build_memory(kind, 1000, cfg));
    }
    try {
        accel::check_build_memory(accel::AccelKind::bvh_sah, 1000000000, cfg);
    } catch (const accel::MemoryLimitError& e) {
        CHECK(std::string(e.what()) ==
              "bvh-sah: building over 1000000000 triangles needs about 34332.3 MiB, more than max_memory = 1024.0 MiB (1073741824 bytes)");
    }
    // Through make_accel: just under the start check's bytes throws before the build starts; at
    // those bytes or the measured peak, whichever is more, it builds.
    const engine::Mesh m = engine::make_icosphere({0, 0, 0}, 1.0f, 3);
    for (auto kind : {accel::AccelKind::brute, accel::AccelKind::bvh_median, accel::AccelKind::bvh_sah, accel::AccelKind::lbvh}) {
        CAPTURE(accel::to_string(kind));
        const std::uint64_t need = accel::build_start_bytes(kind, m.triangle_count(), {});
        cfg.max_memory = need - 1;
        const std::string e = error_of<accel::MemoryLimitError>([&] { (void)accel::make_accel(kind, m.view(), cfg); });
        CHECK(e.find(": building over " + std::to_string(m.triangle_count()) + " triangles needs about") != std::string::npos);
        const std::uint64_t peak = accel::make_accel(kind, m.view(), {})->stats().build_peak_bytes;
        cfg.max_memory = std::max(need, peak);
        CHECK(accel::make_accel(kind, m.view(), cfg)->stats().triangles == m.triangle_count());
    }
    // The kd-tree's own check as it grows, behind a lower-bound estimate: also a MemoryLimitError.
    cfg.max_memory = accel::build_memory_estimate(accel::AccelKind::kdtree, m.triangle_count(), {});
    CHECK_THROWS_AS((void)accel::make_accel(accel::AccelKind::kdtree, m.view(), cfg), accel::MemoryLimitError);
}


TEST_CASE("memory budget: a BVH's layouts are checked against the limit before they are made, from their exact sizes") {
    const engine::Mesh m = peeling_chains(50, 60);
    // Past the estimate's check (make_accel): the BVH builds themselves, whose layouts are checked
    // against what the binary tree leaves of the limit.
    for (const BvhBuilder& b : bvh_builders)
        for (accel::Layouts layouts : {accel::Layouts::all, accel::Layouts::scalar})
            for (bool compact : {false, true}) {
                if (compact && layouts == accel::Layouts::scalar) continue;
                accel::BuildConfig cfg;
                cfg.bvh.max_leaf_size = 1;
                cfg.bvh.simd_leaf_floor = 1;  // one triangle per binary leaf: the layouts dominate the peak
                cfg.layouts = layouts;
                cfg.compact = compact;
                CAPTURE(accel::to_string(b.kind));
                CAPTURE(int(layouts));
                CAPTURE(compact);
                const auto build = [&] { return accel::build_bvh_accel(b.kind, m.view(), cfg, b.build); };
                const std::uint64_t peak = build()->stats().build_peak_bytes;
                // The peak itself is allowed: the checks refuse nothing that fits.
                cfg.max_memory = peak;
                CHECK(build()->stats().build_peak_bytes == peak);
                // A byte less is refused before the layouts are made (the safety net after the
                // build says "the build reached"): the scalar one from the tree, the SIMD one from
                // its plan, the compact one from its sizes; one line naming the structure and the
                // limit. (With the scalar layout asked for, no compact build replaces the default.)
                cfg.max_memory = peak - 1;
                const std::string e = error_of<accel::MemoryLimitError>([&] { (void)build(); });
                CAPTURE(e);
                CHECK(e.rfind(std::string(accel::to_string(b.kind)) + ": ", 0) == 0);
                CHECK(e.find("max_memory = ") != std::string::npos);
                CHECK(e.find("(" + std::to_string(peak - 1) + " bytes)") != std::string::npos);
                if (layouts == accel::Layouts::scalar)
                    CHECK(e.find("its binary tree and scalar layout need") != std::string::npos);
                else if (compact)
                    CHECK((e.find("-wide compact layout needs") != std::string::npos ||
                           e.find("-wide SIMD layout needs") != std::string::npos));
                else
                    CHECK(e.find("-wide SIMD layout needs") != std::string::npos);
            }
}

TEST_CASE("memory budget: past the start check, a build is refused before it allocates past the limit") {
    std::vector<engine::Mesh> meshes = budget_meshes();
    meshes.push_back(peeling_chains(50, 60));
    using accel::AccelKind;
    for (const auto& m : meshes)
        for (AccelKind kind : {AccelKind::bvh_median, AccelKind::bvh_sah, AccelKind::lbvh})
            for (std::uint32_t leaf : {1u, 4u, 16u})
                for (std::uint32_t floor : {0u, 1u})
                    for (accel::Layouts layouts : {accel::Layouts::all, accel::Layouts::simd}) {
                        accel::BuildConfig cfg;
                        cfg.bvh.max_leaf_size = leaf;
                        cfg.bvh.simd_leaf_floor = floor;
                        cfg.layouts = layouts;
                        cfg.max_memory = accel::build_start_bytes(kind, m.triangle_count(), cfg);
                        CAPTURE(accel::to_string(kind));
                        CAPTURE(m.triangle_count());
                        CAPTURE(leaf);
                        CAPTURE(floor);
                        CAPTURE(int(layouts));
                        const std::string e = error_of<accel::MemoryLimitError>([&] { (void)accel::make_accel(kind, m.view(), cfg); });
                        CAPTURE(e);
                        // Built, or refused by the binary tree's count as it grows (bvh-median,
                        // bvh-sah) or before a layout was made; never by the safety net after the
                        // build ("the build reached"). The lbvh's start check covers its whole
                        // binary tree.
                        const bool tree = e.find("building its binary tree went past max_memory") != std::string::npos;
                        CHECK((e == "no error" || tree || e.find("layout need") != std::string::npos));
                        if (kind == AccelKind::lbvh) CHECK(!tree);
                    }
}

TEST_CASE("memory budget: the top-down builders count their nodes exactly: at their peak they build, a byte less is refused") {
    std::vector<engine::Mesh> meshes = budget_meshes();
    meshes.push_back(peeling_chains(50, 60));
    for (const auto& m : meshes)
        for (accel::BvhPrimBuilder builder : {accel::BvhPrimBuilder(accel::build_bvh_sah), accel::BvhPrimBuilder(accel::build_bvh_median)})
            for (std::uint32_t leaf : {1u, 4u}) {
                accel::BvhBuildConfig cfg;
                cfg.max_leaf_size = leaf;
                cfg.parallel_threshold = 64;  // (chunks and top nodes both, on these small meshes)
                const std::size_t peak = builder(accel::make_build_prims(m.view()), cfg).build_peak_bytes;
                CAPTURE(m.triangle_count());
                CAPTURE(leaf);
                cfg.max_bytes = peak;
                const accel::BinaryBvh at = builder(accel::make_build_prims(m.view()), cfg);
                CHECK(at.build_peak_bytes == peak);
                cfg.max_bytes = peak - 1;
                const std::string e = error_of<accel::MemoryLimitError>(
                    [&] { (void)builder(accel::make_build_prims(m.view()), cfg); });
                CHECK(e.rfind("building its binary tree went past max_memory = ", 0) == 0);
                CHECK(e.find("(" + std::to_string(peak - 1) + " bytes)") != std::string::npos);
            }
}

TEST_CASE("memory budget: a SIMD-only BVH whose default layout would not fit is built in compact mode when that fits") {
    const engine::Mesh m = engine::make_torus({0, 0, 0}, 2.0f, 0.5f, 120, 60);
    const std::vector<accel::Ray> rays = testing::random_rays_inside(m.bounds, 4096, 7);
    for (const BvhBuilder& b : bvh_builders) {
        const accel::AccelKind kind = b.kind;
        CAPTURE(accel::to_string(kind));
        accel::BuildConfig cfg;
        cfg.layouts = accel::Layouts::simd;
        const auto build = [&](const accel::BuildConfig& c) { return accel::build_bvh_accel(kind, m.view(), c, b.build); };
        const std::size_t default_peak = build(cfg)->stats().build_peak_bytes;
        accel::BuildConfig compact = cfg;
        compact.compact = true;
        const auto asked = build(compact);
        const std::size_t compact_peak = asked->stats().build_peak_bytes;
        REQUIRE(compact_peak < default_peak);
        // At the default's peak: the default layout.
        cfg.max_memory = default_peak;
        CHECK(build(cfg)->stats().compact_fallback.empty());
        CHECK(build(cfg)->stats().build_peak_bytes == default_peak);
        // Below it, down to compact mode's peak: compact mode, saying why, within the limit, and
        // answering as a compact build asked for.
        for (std::uint64_t limit : {std::uint64_t(default_peak - 1), std::uint64_t(compact_peak)}) {
            cfg.max_memory = limit;
            const auto a = build(cfg);
            const std::string& why = a->stats().compact_fallback;
            CAPTURE(why);
            CHECK(why.rfind(std::string(accel::to_string(kind)) + ": its ", 0) == 0);
            CHECK(why.find("-wide SIMD layout needs") != std::string::npos);
            CHECK(a->stats().build_peak_bytes <= limit);
            CHECK(a->stats().memory_bytes == asked->stats().memory_bytes);
            CHECK(!a->offer().runs(accel::TracePath::scalar, accel::Query::closest));
            for (auto query : {accel::Query::closest, accel::Query::any}) {
                std::vector<accel::Hit> got(rays.size()), want(rays.size());
                a->trace(rays, got, {query, accel::TracePath::single});
                asked->trace(rays, want, {query, accel::TracePath::single});
                CHECK(std::memcmp(got.data(), want.data(), got.size() * sizeof(accel::Hit)) == 0);
            }
        }
        // Below compact mode's peak: refused, by the binary tree (when its build is that peak) or
        // saying why for both layouts.
        cfg.max_memory = compact_peak - 1;
        const std::string e = error_of<accel::MemoryLimitError>([&] { (void)build(cfg); });
        CAPTURE(e);
        CHECK(e.rfind(std::string(accel::to_string(kind)) + ": ", 0) == 0);
        if (e.find("binary tree") == std::string::npos) {
            CHECK(e.find("-wide SIMD layout needs") != std::string::npos);
            CHECK(e.find("; in compact mode, its ") != std::string::npos);
            CHECK(e.find("max_memory") == e.rfind("max_memory"));  // (the limit named once)
        }
        // With the scalar layout asked for too: no compact build (it has none).
        cfg.layouts = accel::Layouts::all;
        cfg.max_memory = compact_peak;
        CHECK_THROWS_AS((void)build(cfg), accel::MemoryLimitError);
    }
}

TEST_CASE("memory budget: the scalar layout's size worked out from the tree is the size it takes") {
    for (const engine::Mesh& m : {peeling_chains(10, 40), engine::make_icosphere({0, 0, 0}, 1.0f, 3),
                                  engine::make_torus({0, 0, 0}, 2.0f, 0.5f, 40, 20)}) {
        for (std::uint32_t leaf : {1u, 4u, 16u}) {
            accel::BuildConfig cfg;
            cfg.bvh.max_leaf_size = leaf;
            cfg.bvh.simd_leaf_floor = 1;
            cfg.layouts = accel::Layouts::scalar;
            const auto a = accel::make_accel(accel::AccelKind::bvh_sah, m.view(), cfg);
            // A scalar-only BVH's memory is its scalar layout's.
            const accel::BinaryBvh bvh = accel::build_bvh_sah(accel::make_prim_refs(m.view()), cfg.bvh);
            CAPTURE(leaf);
            CHECK(accel::bvh2_layout_bytes(bvh) == a->stats().memory_bytes);
        }
    }
}
