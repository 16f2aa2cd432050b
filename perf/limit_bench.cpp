// `arbor-bench limit`: the two halves of the limit model (docs/benchmarks.md, "Distance to the
// limit"; scripts/limit_model.py puts them together with `arbor trace`'s achieved rays/s):
//
//   arbor-bench limit kernels [--bandwidth-mib M] [--cache-mib C]
//       the wide node test and the triangle block test timed with hot caches at every width of
//       the build (checked against the scalar oracles first), the TSC rate, the streaming read
//       bandwidth from memory and from the last-level cache at 1 and 2 threads, and the bytes of a
//       node and a block; one JSON line.
//   arbor-bench limit count --scene MODEL --rays FILE.rays [--accel NAME] [--occluded]
//       the structure built as `arbor trace` builds it, every ray walked by the counted single-ray
//       walk of its N-wide layout (WideBvhAccel::trace_counted): node tests, blocks and triangles
//       per ray, its hits checked against TracePath::single's bit for bit; one JSON line.
//
// Needs the native build (the release preset): the counted walk is instantiated here, with the
// build's -march, not through a kernel set's table.
#include "perf/commands.h"
#include "perf/limit_kernels.h"

#include "accel/dispatch/kernel_entries.h"
#include "accel/factory/make_accel.h"
#include "accel/structures/kdtree_accel.h"
#include "accel/structures/wide_paths_impl.h"
#include "engine/mesh_loader.h"
#include "engine/rayfile.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

using namespace arbor;

namespace {

using nlohmann::json;

json kernels_json(std::size_t bandwidth_mib, std::size_t cache_mib) {
    const double ghz = perf::tsc_ghz();
    json out;
    out["tsc_ghz"] = ghz;
    out["kernels"] = json::array();
    for (const perf::KernelTimes& k : perf::time_wide_kernels(ghz))
        out["kernels"].push_back({{"width", k.width},
                                  {"node_ns", k.node_ns},
                                  {"node_ns_median", k.node_ns_median},
                                  {"node_tsc_cycles", k.node_cycles},
                                  {"block_ns", k.block_ns},
                                  {"block_ns_median", k.block_ns_median},
                                  {"block_tsc_cycles", k.block_cycles},
                                  {"node_chain_ns", k.node_chain_ns},
                                  {"node_chain_ns_median", k.node_chain_ns_median},
                                  {"node_chain_tsc_cycles", k.node_chain_cycles},
                                  {"checked_lanes", k.checked_tests},
                                  {"box_hit_fraction", k.box_hit_fraction},
                                  {"block_hit_fraction", k.block_hit_fraction}});
    const perf::Bandwidth b = perf::measure_bandwidth(bandwidth_mib, cache_mib);
    out["bandwidth"] = {{"buffer_mib", b.buffer_mib},
                        {"gbs_1_thread", b.gbs_1},
                        {"gbs_2_threads", b.gbs_2},
                        {"cache_mib", b.cache_mib},
                        {"cache_gbs_1_thread", b.cache_gbs_1},
                        {"cache_gbs_2_threads", b.cache_gbs_2}};
    // Bytes a walk reads per node (its boxes, children, counts, and its order row for the ray's
    // octant) and per block (the SoA vertices; the ids only for a hit), per width.
    out["bytes"] = json::array();
    const auto sizes = [&](auto width) {
        constexpr std::size_t n = decltype(width)::value;
        out["bytes"].push_back({{"width", n},
                                {"node", sizeof(accel::WideNode<n>)},
                                {"node_order_row", n},
                                {"block", sizeof(accel::WideBlock<n>)},
                                {"block_vertices", sizeof(simd::TrisSoA<n>)}});
    };
    sizes(std::integral_constant<std::size_t, 16>{});
    sizes(std::integral_constant<std::size_t, 8>{});
    sizes(std::integral_constant<std::size_t, 4>{});
    return out;
}

/// The counted walk of a WideBvhAccel<N> (or of a kd-tree's cell paths), and its hits against
/// TracePath::single's. False when `a` is not one of width N.
template <std::size_t N>
bool count_width(const accel::Accel& a, std::span<const accel::Ray> rays, accel::Query query, json& out) {
    const accel::Accel* target = &a;
    if (const auto* kd = dynamic_cast<const accel::KdTreeAccel*>(&a); kd && kd->cell_paths()) target = kd->cell_paths();
    const auto* wide = dynamic_cast<const accel::WideBvhAccel<N>*>(target);
    if (!wide) return false;
    std::vector<accel::Hit> counted(rays.size()), single(rays.size());
    accel::WideCounts c;
    wide->trace_counted(rays, counted, query, c);
    a.trace(rays, single, {query, accel::TracePath::single});
    std::size_t differ = 0, hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        hits += counted[i].is_hit();
        differ += std::memcmp(&counted[i], &single[i], sizeof(accel::Hit)) != 0;
    }
    if (differ != 0)
        throw std::runtime_error("limit count: the counted walk's hits differ from TracePath::single's on " +
                                 std::to_string(differ) + " rays");
    const auto& layout = wide->wide_layout();
    const double n = double(std::max<std::uint64_t>(c.rays, 1));
    out["width"] = N;
    out["rays"] = c.rays;
    out["hits"] = hits;
    out["node_tests_per_ray"] = double(c.node_tests) / n;
    out["blocks_per_ray"] = double(c.blocks) / n;
    out["triangles_per_ray"] = double(c.triangles) / n;
    out["node_bytes"] = sizeof(accel::WideNode<N>) + N;  // the node and its order row
    out["block_bytes"] = sizeof(accel::WideBlock<N>);
    out["layout_nodes"] = layout.nodes.size();
    out["layout_blocks"] = layout.blocks.size();
    out["layout_bytes"] = layout.memory_bytes();
    return true;
}

json count_json(const std::string& scene, const std::string& rays_path, const std::string& accel_name, bool occluded) {
    const auto kind = accel::parse_accel_kind(accel_name);
    if (!kind || *kind == accel::AccelKind::automatic || *kind == accel::AccelKind::brute)
        throw std::invalid_argument("--accel: '" + accel_name + "' is not one of bvh-median, bvh-sah, lbvh, kdtree");
    engine::Warnings warnings;
    const engine::Mesh mesh = engine::load_mesh(scene, warnings);
    const std::vector<accel::Ray> rays = engine::read_rays(rays_path);
    accel::BuildConfig cfg;
    cfg.layouts = accel::Layouts::simd;  // as `arbor trace --path best` builds it
    const auto built = accel::make_accel(*kind, mesh.view(), cfg);
    const accel::Query query = occluded ? accel::Query::any : accel::Query::closest;
    json out{
        {"scene", scene}, {"rays_file", rays_path}, {"accel", accel_name}, {"query", occluded ? "any" : "closest"}};
    bool done = false;
#if XSIMD_WITH_AVX512F
    done = done || count_width<16>(*built, rays, query, out);
#endif
#if XSIMD_WITH_AVX2
    done = done || count_width<8>(*built, rays, query, out);
#endif
    done = done || count_width<4>(*built, rays, query, out);
    if (!done)
        throw std::runtime_error("limit count: " + accel_name + " was not built as a wide BVH (no counted walk)");
    return out;
}

int usage_error(const std::string& message) {
    std::fprintf(stderr, "arbor-bench limit: %s\n", message.c_str());
    return 2;
}

}  // namespace

int arbor::perf::limit_command(int argc, char** argv) {
    if (argc < 2 || std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0) {
        std::fprintf(argc < 2 ? stderr : stdout,
                     "Usage: arbor-bench limit kernels [--bandwidth-mib M] [--cache-mib C]\n"
                     "       arbor-bench limit count --scene MODEL --rays FILE.rays [--accel NAME] [--occluded]\n");
        return argc < 2 ? 2 : 0;
    }
    const std::string sub = argv[1];
    CLI::App app{"arbor-bench limit " + sub};
    std::size_t mib = 512, cache_mib = 8;
    std::string scene, rays, accel_name = "bvh-sah";
    bool occluded = false;
    if (sub == "kernels") {
        app.add_option("--bandwidth-mib", mib, "buffer of the streaming read from memory, MiB")
            ->check(CLI::Range(64, 65536));
        app.add_option("--cache-mib", cache_mib, "buffer of the streaming read from the caches, MiB")
            ->check(CLI::Range(1, 64));
    } else if (sub == "count") {
        app.add_option("--scene", scene, "model file")->required();
        app.add_option("--rays", rays, ".rays file")->required();
        app.add_option("--accel", accel_name, "bvh-median, bvh-sah, lbvh or kdtree");
        app.add_flag("--occluded", occluded, "any-hit queries (shadow rays)");
    } else {
        return usage_error("unknown mode '" + sub + "' (expected kernels or count)");
    }
    try {
        app.parse(argc - 1, argv + 1);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    try {
        const json out =
            sub == "kernels" ? kernels_json(mib, cache_mib) : count_json(scene, rays, accel_name, occluded);
        std::printf("%s\n", out.dump().c_str());
        return 0;
    } catch (const std::invalid_argument& e) {
        return usage_error(e.what());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "arbor-bench limit %s: %s\n", sub.c_str(), e.what());
        return 1;
    }
}
