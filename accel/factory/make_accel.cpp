// make_accel and what each structure reports before it is built (make_accel.h).
#include "accel/factory/make_accel.h"

#include "accel/bvh/bvh_build.h"
#include "accel/factory/memory_estimate.h"
#include "accel/lbvh/lbvh_build.h"
#include "accel/structures/brute_accel.h"

#include <stdexcept>
#include <string>

namespace arbor::accel {

namespace {
std::unique_ptr<Accel> build(AccelKind kind, const TriangleView& tris, const BuildConfig& cfg) {
    switch (kind) {
    case AccelKind::brute: return std::make_unique<BruteAccel>(tris);
    case AccelKind::bvh_median: return build_bvh_accel(kind, tris, cfg, build_bvh_median);
    case AccelKind::bvh_sah: return build_bvh_accel(kind, tris, cfg, build_bvh_sah);
    case AccelKind::lbvh: return build_bvh_accel(kind, tris, cfg, build_lbvh);
    case AccelKind::kdtree: return make_kdtree_accel(tris, cfg);
    case AccelKind::automatic: throw std::invalid_argument("make_accel: resolve 'auto' before building");
    default: break;
    }
    throw std::invalid_argument("structure '" + std::string(to_string(kind)) + "' is not available in this build yet");
}

bool is_bvh(AccelKind kind) {
    return kind == AccelKind::bvh_median || kind == AccelKind::bvh_sah || kind == AccelKind::lbvh;
}
}  // namespace

std::unique_ptr<Accel> make_accel(AccelKind kind, const TriangleView& tris, const BuildConfig& cfg) {
    if (kind != AccelKind::automatic) check_build_memory(kind, tris.triangle_count(), cfg);
    std::unique_ptr<Accel> a = build(kind, tris, cfg);
    // A safety net behind the estimate (which bounds the BVHs and brute from above; the kd-tree
    // builder checks as it grows): a measured peak over the limit is refused too.
    if (cfg.max_memory != 0 && a->stats().build_peak_bytes > cfg.max_memory)
        throw MemoryLimitError(std::string(to_string(kind)) + ": the build reached " + std::to_string(a->stats().build_peak_bytes) +
                               " bytes, more than max_memory = " + std::to_string(cfg.max_memory) + " bytes");
    return a;
}

PathOffer expected_offer(AccelKind kind, const BuildConfig& cfg) {
    if (kind == AccelKind::brute) return brute_offer();
    if (is_bvh(kind)) return bvh_offer(cfg);
    if (kind == AccelKind::kdtree) return kdtree_offer(cfg);
    return {};
}

std::vector<std::string> skipped_by_build(AccelKind kind, const BuildConfig& cfg) {
    if (is_bvh(kind)) return bvh_skipped(cfg, bvh_leaf_floor(cfg));
    if (kind == AccelKind::kdtree) return kdtree_skipped(cfg);
    return {};  // brute: no layouts
}

}  // namespace arbor::accel
