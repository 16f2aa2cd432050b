#include "apps/arbor/common.h"

#include "engine/error.h"
#include "engine/memory_budget.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

namespace arbor::app {

CLI::Option* add_accel_option(CLI::App& cmd, std::string& name) {
    return cmd.add_option("--accel", name, "acceleration structure: " + accel::accel_kind_names())
        ->check([](const std::string& v) -> std::string {
            if (accel::parse_accel_kind(v)) return {};
            return "unknown structure '" + v + "' (expected one of " + accel::accel_kind_names() + ")";
        });
}

std::vector<std::string> split_list(const std::string& s) {
    std::vector<std::string> out;
    std::size_t b = 0;
    while (true) {
        const std::size_t e = s.find(',', b);
        out.push_back(s.substr(b, e == std::string::npos ? std::string::npos : e - b));
        if (e == std::string::npos) return out;
        b = e + 1;
    }
}

CLI::Option* add_accel_list_option(CLI::App& cmd, std::string& names) {
    return cmd.add_option("--accel", names, "acceleration structure, or a comma list for --integrator cost: " + accel::accel_kind_names())
        ->check([](const std::string& v) -> std::string {
            for (const std::string& n : split_list(v))
                if (!accel::parse_accel_kind(n))
                    return "unknown structure '" + n + "' (expected one of " + accel::accel_kind_names() + ")";
            return {};
        });
}

void add_build_options(CLI::App& cmd, accel::BuildConfig& cfg) {
    cmd.add_option("--leaf-size", cfg.bvh.max_leaf_size, "most triangles per BVH leaf")
        ->check(CLI::Range(1u, 1u << 16))
        ->capture_default_str();
    cmd.add_option("--sah-bins", cfg.bvh.sah_bins, "bins per axis of the binned SAH build (bvh-sah)")
        ->check(CLI::Range(2u, 32u))
        ->capture_default_str();
    cmd.add_option("--max-memory", cfg.max_memory,
                   "most bytes the build may use, e.g. 2G or 512M (powers of 1024; default: no limit); trace and "
                   "info also refuse input files that would not fit")
        ->transform(CLI::Validator(
            [](std::string& v) -> std::string {
                const auto bytes = engine::parse_byte_size(v);
                if (!bytes) return "'" + v + "' is not a size in bytes (e.g. 2G, 512M, 100000)";
                v = std::to_string(*bytes);
                return {};
            },
            "BYTES"));
    cmd.add_option("--simd-leaf-floor", cfg.bvh.simd_leaf_floor,
                   "BVHs traced on a SIMD path: ranges of at most this many triangles are not split (0: the SIMD "
                   "layout's width; 1: none, the binary tree of the scalar path)")
        ->check(CLI::Range(0u, 1u << 16))
        ->capture_default_str();
    cmd.add_option("--bvh-width", cfg.wide.width, "children per node of the BVHs' SIMD layout: 4, 8 or 16 (default: the measured best)")
        ->check(CLI::IsMember({4u, 8u, 16u}));
    cmd.add_flag("--compact", cfg.compact,
                 "BVHs: keep the compact layout (8-bit quantized child boxes, leaves as blocks of triangles with their "
                 "own vertex copies): about half the bytes per triangle, traced on the single and packet paths "
                 "(docs/structures.md)");
    cmd.add_option("--kd-walk", cfg.kd_blocks.walk,
                   "the kd-tree's SIMD paths: tight-cells (default: its non-empty cells as a wide BVH, boxes cut to "
                   "their triangles, the BVHs' walks), cells (the pure cells) or ropes (its nodes, rope and stack walks)")
        ->transform(CLI::CheckedTransformer(std::map<std::string, accel::KdWalk>{{"ropes", accel::KdWalk::ropes},
                                                                                {"cells", accel::KdWalk::cells},
                                                                                {"tight-cells", accel::KdWalk::tight_cells}}));
}

CLI::Option* add_threads_option(CLI::App& cmd, int& threads) {
    return cmd.add_option("--threads", threads, "worker threads (default: all)")->check(CLI::Range(1, 4096));
}

std::unique_ptr<tbb::global_control> limit_threads(int threads) {
    if (threads <= 0) return nullptr;
    return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
}

int active_threads() {
    return int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
}

accel::AccelPick resolve_accel(const std::string& name, const accel::AutoJob& job) {
    const auto kind = accel::parse_accel_kind(name);
    if (!kind) throw OptionError("--accel: unknown structure '" + name + "'");
    return accel::pick_accel(*kind, job);
}

accel::AccelPick resolve_accel(const std::string& name, const accel::TriangleView& tris, const accel::BuildConfig& build) {
    accel::AutoJob job;
    job.tris = tris;
    job.build = build;
    return resolve_accel(name, job);
}

void put_stats(nlohmann::json& j, const accel::BuildStats& s) {
    j["nodes"] = s.nodes;
    j["leaves"] = s.leaves;
    j["max_depth"] = s.max_depth;
    j["mean_leaf_depth"] = s.mean_leaf_depth;
    j["sah_cost"] = s.sah_cost;
    j["bytes_per_triangle"] = s.bytes_per_triangle();
    j["memory_bytes"] = s.memory_bytes;
    j["build_peak_bytes"] = s.build_peak_bytes;
    j["dropped_nonfinite"] = s.dropped_nonfinite;
}

}  // namespace arbor::app
