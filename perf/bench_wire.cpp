#include "perf/bench_wire.h"

#include <nlohmann/json.hpp>

#include <stdexcept>

namespace arbor::perf {

// Every field, listed: a field added to BenchRow or AutoRow must be added here too, or `mpirun
// arbor bench` drops it. The size checks below fail the build until it is (x86-64, libstdc++).
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Stat3, median, min, max)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(BenchRow, scene, family, kind, query, structure, path, best_path, embree, threads,
                                   host, rank, triangles, rays, validated_rays, build_ms, trace_ms, mrays,
                                   build_samples, trace_samples, trace_cpu_samples, trace_cpu_ms, nodes, leaves,
                                   max_depth, sah_cost, bytes_per_triangle, nodes_per_ray, tris_per_ray, brute_sample,
                                   err_brute, err_scalar, err_embree, ratio_embree, total_ms, total_cpu_ms, shape)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(AutoRow, scene, kind, threads, budget, picked, picked_path, best, best_path, auto_ms,
                                   auto_total_ms, best_ms, default_ms, regret, regret_without_auto, regret_cpu, probed,
                                   oracle_split_regret, oracle_split_regret_cpu, same_twice, same_twice_cpu, reason)
static_assert(sizeof(BenchRow) == 600, "BenchRow changed: list the new field in bench_wire.cpp, then update this size");
static_assert(sizeof(AutoRow) == 328, "AutoRow changed: list the new field in bench_wire.cpp, then update this size");

std::string to_wire(const BenchResult& r) {
    const nlohmann::json j = {{"rows", r.rows}, {"autos", r.autos}, {"notes", r.notes}};
    const std::vector<std::uint8_t> bytes = nlohmann::json::to_cbor(j);
    return std::string(bytes.begin(), bytes.end());
}

BenchResult from_wire(std::string_view bytes) {
    try {
        const nlohmann::json j = nlohmann::json::from_cbor(bytes.begin(), bytes.end());
        BenchResult r;
        r.rows = j.at("rows").get<std::vector<BenchRow>>();
        r.autos = j.at("autos").get<std::vector<AutoRow>>();
        r.notes = j.at("notes").get<std::vector<std::string>>();
        return r;
    } catch (const nlohmann::json::exception& e) {
        throw std::runtime_error(std::string("benchmark rows from another rank are unreadable: ") + e.what());
    }
}

}  // namespace arbor::perf
