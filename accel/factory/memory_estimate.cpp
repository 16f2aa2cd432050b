#include "accel/factory/memory_estimate.h"

#include <cstdio>

namespace arbor::accel {

namespace {
std::string mib(std::uint64_t bytes) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.1f MiB", double(bytes) / 1048576.0);
    return buf;
}
}  // namespace

std::uint64_t build_memory_estimate(AccelKind kind, std::size_t triangles, const BuildConfig&) {
    const std::uint64_t n = triangles;
    switch (kind) {
    case AccelKind::brute: return 40 * n;  // three corners and an id per triangle (BruteAccel::Tri)
    case AccelKind::bvh_median:
    case AccelKind::bvh_sah:
    case AccelKind::lbvh: return 384 * n + (64u << 10);
    case AccelKind::kdtree: return 64 * n;
    case AccelKind::automatic: break;
    }
    return 0;
}

void check_build_memory(AccelKind kind, std::size_t triangles, const BuildConfig& cfg) {
    if (cfg.max_memory == 0) return;
    const std::uint64_t need = build_memory_estimate(kind, triangles, cfg);
    if (need > cfg.max_memory)
        throw MemoryLimitError(std::string(to_string(kind)) + ": building over " + std::to_string(triangles) +
                               " triangles needs about " + mib(need) + ", more than max_memory = " + mib(cfg.max_memory) +
                               " (" + std::to_string(cfg.max_memory) + " bytes)");
}

}  // namespace arbor::accel
