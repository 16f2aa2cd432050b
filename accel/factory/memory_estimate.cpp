#include "accel/factory/memory_estimate.h"

namespace arbor::accel {

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

std::uint64_t build_start_bytes(AccelKind kind, std::size_t triangles, const BuildConfig& cfg) {
    const std::uint64_t n = triangles;
    // bvh-median, bvh-sah: 32 bytes per prim and 4 per id; their nodes are counted as the build
    // makes them (BvhBuildConfig::max_bytes). lbvh: its whole binary build, 2 x 64 bytes for the
    // nodes (the chunks and the tree), the keys, sorted references and sort buffers besides.
    switch (kind) {
    case AccelKind::bvh_median:
    case AccelKind::bvh_sah: return 36 * n + (64u << 10);
    case AccelKind::lbvh: return 208 * n + (64u << 10);
    default: return build_memory_estimate(kind, triangles, cfg);
    }
}

void check_build_memory(AccelKind kind, std::size_t triangles, const BuildConfig& cfg) {
    if (cfg.max_memory == 0) return;
    const std::uint64_t need = build_start_bytes(kind, triangles, cfg);
    if (need > cfg.max_memory)
        throw MemoryLimitError(std::string(to_string(kind)) + ": building over " + std::to_string(triangles) +
                               " triangles needs about " + mib_text(need) + ", more than " +
                               max_memory_text(cfg.max_memory));
}

}  // namespace arbor::accel
